//! Memory a scene will take, estimated from its triangle count before anything of that size
//! is built, and compared with what this process can still get: its address-space limit
//! (`ulimit -v`) less what it already maps, and the machine's available memory. The triangle
//! limit (`MAX_SCENE_TRIANGLES`) says what a device could draw; this says whether this
//! process can build it. Past it a run is refused with the figures instead of aborting
//! (`memory allocation of N bytes failed`) in the middle of building, which no error
//! handler sees.
//!
//! What one triangle costs depends on what will render it, so the command sets that before
//! it loads the scene ([`set_renderer`]); the figures are peak virtual memory measured on
//! `random-cubes` (the ray tracer's motion BVH dominates its figure) with a margin.

use std::sync::atomic::{AtomicU64, Ordering};

/// Bytes a triangle takes on the GPU path at its peak: the mesh (t0 and t1, 72 B), the
/// interleaved vertex record (96 B), its staging copy and the device buffer (96 B each, in
/// host memory on lavapipe). Measured: 4.8 million triangles need 1.5 to 2 GB.
pub const GPU_BYTES_PER_TRIANGLE: u64 = 384;
/// Bytes a triangle takes when ray traced: the mesh, the f64 triangle records and the
/// motion BVH with the vectors it grows. Measured: 4.8 million triangles need 3.5 to 4 GB.
pub const RAYTRACE_BYTES_PER_TRIANGLE: u64 = 1024;

static BYTES_PER_TRIANGLE: AtomicU64 = AtomicU64::new(GPU_BYTES_PER_TRIANGLE);

/// What will render the scenes this process loads: the ray tracer (`raytrace`) or the GPU.
pub fn set_renderer(raytrace: bool) {
    let bytes = if raytrace {
        RAYTRACE_BYTES_PER_TRIANGLE
    } else {
        GPU_BYTES_PER_TRIANGLE
    };
    BYTES_PER_TRIANGLE.store(bytes, Ordering::Relaxed);
}

/// Ok when `triangles` more fit in what this process can still use; otherwise the reason,
/// with the figures.
pub fn check_triangles(triangles: u64) -> Result<(), String> {
    let per = BYTES_PER_TRIANGLE.load(Ordering::Relaxed);
    let path = if per == RAYTRACE_BYTES_PER_TRIANGLE {
        "ray traced"
    } else {
        "rendered on the GPU"
    };
    check_bytes(
        triangles.saturating_mul(per),
        &format!("{triangles} triangles"),
        &format!("{per} bytes each, built and {path}"),
        "building, use fewer triangles (or a lower --subdivide / --cubes)",
    )
}

/// Ok when `bytes` more fit in what this process can still use; otherwise the reason: `what`
/// would need about so many GiB (`how`: the figure it comes from), more than the process can
/// still use (and what bounds that); refused before `advice` (what is not done, and what to
/// do instead).
pub fn check_bytes(bytes: u64, what: &str, how: &str, advice: &str) -> Result<(), String> {
    let Some((left, bound)) = headroom() else {
        return Ok(());
    };
    if bytes <= left {
        return Ok(());
    }
    Err(format!(
        "{what} would need about {:.1} GiB ({how}), more than the {:.1} GiB this process can \
         still use ({bound}); refused before {advice}",
        gib(bytes),
        gib(left)
    ))
}

fn gib(bytes: u64) -> f64 {
    bytes as f64 / f64::from(1u32 << 30)
}

/// Bytes this process can still get and what bounds them; `None` where neither bound can
/// be read (not Linux).
fn headroom() -> Option<(u64, String)> {
    let address_space = address_space_left().map(|(left, limit)| {
        (
            left,
            format!(
                "its address-space limit, ulimit -v, is {:.1} GiB",
                gib(limit)
            ),
        )
    });
    let available =
        available_memory().map(|b| (b, "the machine's available memory and swap".to_owned()));
    match (address_space, available) {
        (Some(a), Some(m)) => Some(if a.0 <= m.0 { a } else { m }),
        (a, m) => a.or(m),
    }
}

/// The soft address-space limit less what the process maps now, and the limit; `None`
/// when unlimited.
fn address_space_left() -> Option<(u64, u64)> {
    #[cfg(unix)]
    {
        let mut limit = libc::rlimit {
            rlim_cur: 0,
            rlim_max: 0,
        };
        // SAFETY: getrlimit writes the struct passed; nothing else is touched.
        if unsafe { libc::getrlimit(libc::RLIMIT_AS, &mut limit) } != 0
            || limit.rlim_cur == libc::RLIM_INFINITY
        {
            return None;
        }
        // rlim_t is u64 on Linux, not on every Unix.
        #[allow(clippy::unnecessary_cast)]
        let limit = limit.rlim_cur as u64;
        let used = proc_kib("/proc/self/status", "VmSize:").unwrap_or(0);
        Some((limit.saturating_sub(used), limit))
    }
    #[cfg(not(unix))]
    None
}

/// MemAvailable plus free swap (Linux).
fn available_memory() -> Option<u64> {
    let available = proc_kib("/proc/meminfo", "MemAvailable:")?;
    Some(available + proc_kib("/proc/meminfo", "SwapFree:").unwrap_or(0))
}

/// A `Key:  N kB` line of a /proc file, in bytes.
fn proc_kib(file: &str, key: &str) -> Option<u64> {
    let text = std::fs::read_to_string(file).ok()?;
    let line = text.lines().find(|l| l.starts_with(key))?;
    let kib: u64 = line[key.len()..]
        .trim()
        .trim_end_matches("kB")
        .trim()
        .parse()
        .ok()?;
    Some(kib * 1024)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_count_no_machine_holds_is_refused_with_figures_and_a_small_one_passes() {
        assert!(check_triangles(1000).is_ok());
        if headroom().is_some() {
            let e = check_triangles(u64::MAX / 2048).unwrap_err();
            assert!(e.contains("GiB") && e.contains("bytes each"), "{e}");
        }
    }
}
