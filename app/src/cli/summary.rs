//! The human-readable summary of a render (the `--json` output is `FrameStats` itself).

use crate::render::FrameStats;
use std::fmt::Write;

fn mib(bytes: u64) -> String {
    format!("{:.2} MiB", bytes as f64 / (1024.0 * 1024.0))
}

pub fn summary_text(stats: &FrameStats, files: &[String]) -> String {
    let mut s = String::new();
    let _ = writeln!(
        s,
        "{} / {}: {}x{}, {} spp, seed {}, shadow map {}x{}, {} triangles",
        stats.scene,
        stats.method,
        stats.width,
        stats.height,
        stats.spp,
        stats.seed,
        stats.shadow_width,
        stats.shadow_height,
        stats.triangles
    );
    let _ = writeln!(s, "device: {}", stats.device);
    for w in &stats.warnings {
        let _ = writeln!(s, "warning: {w}");
    }
    if stats.method == "temporal" || stats.method == "coverage" {
        let _ = writeln!(s, "fragments N_f: {}", stats.fragments);
        let _ = writeln!(s, "ranges    N_r: {}", stats.ranges);
        if stats.method == "coverage" {
            let _ = writeln!(
                s,
                "ranges without the coverage map: {} ({:.1}x more); equation (2) without it: {}; nearest + coverage maps: {}",
                stats.ranges_without_coverage,
                stats.ranges_without_coverage as f64 / stats.ranges.max(1) as f64,
                mib(stats.shadow_map_bytes_eq2_without_coverage),
                mib(stats.coverage_map_bytes)
            );
        }
        let _ = writeln!(
            s,
            "shadow map memory, equation (2): {} ({} bytes); allocated {}",
            mib(stats.shadow_map_bytes_eq2),
            stats.shadow_map_bytes_eq2,
            mib(stats.shadow_map_bytes_allocated)
        );
        if stats.static_layer_bytes > 0 {
            let _ = writeln!(
                s,
                "static layer (nearest static triangle per texel): {}{}",
                mib(stats.static_layer_bytes),
                if stats.static_layer_kept {
                    ", kept from a pass before the timed one"
                } else {
                    ""
                }
            );
        }
        if stats.shadow_pass_attempts > 1 {
            let _ = writeln!(
                s,
                "shadow pass ran {} times (buffers grown to fit)",
                stats.shadow_pass_attempts
            );
        }
    } else {
        let _ = writeln!(
            s,
            "shadow map memory: {}",
            mib(stats.shadow_map_bytes_allocated)
        );
    }
    let _ = writeln!(s, "GPU time per pass:");
    for p in &stats.passes {
        let note = if p.counted() { "" } else { "  (not counted)" };
        let _ = writeln!(s, "  {:<18} {:>10.2} ms{note}", p.pass, p.gpu_ms);
    }
    let _ = writeln!(s, "  {:<18} {:>10.2} ms", "total", stats.frame_ms);
    let _ = writeln!(s, "wall time: {:.1} ms", stats.wall_ms);
    for f in files {
        let _ = writeln!(s, "wrote {f}");
    }
    s
}
