//! Emits the link arguments that a distribution's incomplete `libshaderc.so` lacks; see
//! `src/lib.rs` for why. Emits nothing unless the broken layout is positively recognised.

use std::env;
use std::fs;
use std::path::{Path, PathBuf};
use std::process::Command;

/// Set to `off` (or `0`, `false`, `no`) to emit nothing.
const OPT_OUT: &str = "MOTION_SHADOWS_SHADERC_LINK";

/// The static archives to link instead of `libshaderc.so`, in an order that also suits
/// single-pass linkers (GNU ld): users before providers. `shaderc_combined` is shaderc itself
/// (on Debian only shaderc's own objects); the others are glslang and SPIRV-Tools. Only those
/// that exist are emitted (glslang 14 and later merged MachineIndependent, OSDependent and
/// GenericCodeGen into `libglslang.a` and dropped OGLCompiler and HLSL).
///
/// Why not keep `libshaderc.so` and add only what it lacks: on Debian 12 that links but
/// crashes (SIGSEGV in `spv::Builder::getStringId`), because `libshaderc.so.1` embeds the
/// SPIR-V back end of the older glslang it was built against and `glslang-dev` is newer. The
/// archives below all come from the installed glslang, so they agree with each other.
const STATIC_LIBS: &[&str] = &[
    "shaderc_combined",
    "SPIRV",
    "glslang",
    "MachineIndependent",
    "OSDependent",
    "GenericCodeGen",
    "OGLCompiler",
    "HLSL",
    "SPIRV-Tools-opt",
    "SPIRV-Tools",
];

/// Without these the layout is not the one this crate knows how to complete.
const REQUIRED_STATIC_LIBS: &[&str] = &["shaderc_combined", "glslang", "SPIRV-Tools"];

fn main() {
    println!("cargo:rerun-if-changed=build.rs");
    for var in [
        OPT_OUT,
        "SHADERC_LIB_DIR",
        "VULKAN_SDK",
        "PKG_CONFIG",
        "PKG_CONFIG_PATH",
        "PKG_CONFIG_LIBDIR",
        "PKG_CONFIG_SYSROOT_DIR",
    ] {
        println!("cargo:rerun-if-env-changed={var}");
    }

    match plan() {
        Plan::Nothing(why) => println!("shaderc-link: nothing to do: {why}"),
        Plan::Warn(why) => {
            println!("shaderc-link: nothing emitted: {why}");
            println!("cargo:warning=motion-shadows-shaderc-link: {why}");
        }
        Plan::Link { dir, so, libs } => {
            println!(
                "shaderc-link: {} does not record its glslang/SPIRV-Tools dependencies; \
                 linking shaderc and them from the static archives beside it",
                so.display()
            );
            println!("cargo:rustc-link-search=native={}", dir.display());
            // `-bundle`: the linker reads each archive where it lies instead of rustc copying
            // tens of megabytes of objects into this crate's rlib. rustc puts static libraries
            // (with the rlibs) before all shared ones on the command line, so the program takes
            // shaderc's symbols from the archive and never loads the incomplete libshaderc.so.
            for lib in libs {
                println!("cargo:rustc-link-lib=static:-bundle={lib}");
            }
            println!("cargo:rustc-link-lib=dylib=stdc++");
        }
    }
}

enum Plan {
    Nothing(String),
    Warn(String),
    Link {
        dir: PathBuf,
        so: PathBuf,
        libs: Vec<&'static str>,
    },
}

fn plan() -> Plan {
    if let Ok(value) = env::var(OPT_OUT) {
        if matches!(
            value.to_ascii_lowercase().as_str(),
            "off" | "0" | "false" | "no"
        ) {
            return Plan::Nothing(format!("{OPT_OUT}={value}"));
        }
    }
    let target_os = env::var("CARGO_CFG_TARGET_OS").unwrap_or_default();
    if target_os != "linux" {
        return Plan::Nothing(format!("target os is {target_os:?}, not linux"));
    }
    // shaderc-sys searches these first; what they point at is the user's choice.
    for var in ["SHADERC_LIB_DIR", "VULKAN_SDK"] {
        if env::var_os(var).is_some() {
            return Plan::Nothing(format!("{var} is set"));
        }
    }
    let Some(dir) = shaderc_sys_search_dir() else {
        return Plan::Nothing("no directory where shaderc-sys would look".into());
    };
    let Ok(dir) = fs::canonicalize(&dir) else {
        return Plan::Nothing(format!("{} does not exist", dir.display()));
    };
    let so = dir.join("libshaderc.so");
    let Ok(bytes) = fs::read(&so) else {
        return Plan::Nothing(format!("no readable {}", so.display()));
    };
    // A fixed or reinstalled package reruns this script.
    println!("cargo:rerun-if-changed={}", so.display());
    let dynamic = match parse_dynamic(&bytes) {
        Ok(dynamic) => dynamic,
        Err(why) => return Plan::Nothing(format!("{}: {why}", so.display())),
    };
    let provider_needed = dynamic.needed.iter().any(|name| {
        let name = name.to_ascii_lowercase();
        name.contains("glslang") || name.contains("spirv")
    });
    if provider_needed {
        return Plan::Nothing(format!("{} records its dependencies", so.display()));
    }
    if dynamic.undefined_glslang_or_spvtools == 0 {
        return Plan::Nothing(format!("{} is self-contained", so.display()));
    }
    let libs: Vec<&'static str> = STATIC_LIBS
        .iter()
        .copied()
        .filter(|lib| dir.join(format!("lib{lib}.a")).is_file())
        .collect();
    let missing: Vec<&str> = REQUIRED_STATIC_LIBS
        .iter()
        .copied()
        .filter(|lib| !libs.contains(lib))
        .collect();
    if !missing.is_empty() {
        return Plan::Warn(format!(
            "{} leaves {} glslang/SPIRV-Tools symbols undefined and the static libraries {} \
             are not in {}; linking shaderc will likely fail (on Debian/Ubuntu install \
             libshaderc-dev, glslang-dev and spirv-tools, or enable shaderc's \
             build-from-source feature)",
            so.display(),
            dynamic.undefined_glslang_or_spvtools,
            missing.join(", "),
            dir.display()
        ));
    }
    Plan::Link { dir, so, libs }
}

/// The directory shaderc-sys 0.10 takes its library from when neither `SHADERC_LIB_DIR` nor
/// `VULKAN_SDK` is set: the first `-L` of pkg-config's `shaderc`, else the multiarch directory,
/// else `/usr/lib64` (x86_64), else `/usr/lib`.
fn shaderc_sys_search_dir() -> Option<PathBuf> {
    if let Some(dir) = pkg_config_dir() {
        return Some(dir);
    }
    let arch = env::var("CARGO_CFG_TARGET_ARCH").ok()?;
    let debian_arch = if arch == "x86" { "i386" } else { arch.as_str() };
    let multiarch = PathBuf::from(format!("/usr/lib/{debian_arch}-linux-gnu/"));
    if multiarch.exists() {
        Some(multiarch)
    } else if arch == "x86_64" && Path::new("/usr/lib64/").exists() {
        Some("/usr/lib64/".into())
    } else {
        Some("/usr/lib/".into())
    }
}

fn pkg_config_dir() -> Option<PathBuf> {
    let program = env::var_os("PKG_CONFIG").unwrap_or_else(|| "pkg-config".into());
    // The pkg-config crate shaderc-sys uses sets these too, so system directories are listed.
    let output = Command::new(program)
        .args(["--libs", "shaderc"])
        .env("PKG_CONFIG_ALLOW_SYSTEM_LIBS", "1")
        .env("PKG_CONFIG_ALLOW_SYSTEM_CFLAGS", "1")
        .output()
        .ok()?;
    if !output.status.success() {
        return None;
    }
    String::from_utf8_lossy(&output.stdout)
        .split_whitespace()
        .find_map(|arg| arg.strip_prefix("-L"))
        .map(PathBuf::from)
}

struct Dynamic {
    needed: Vec<String>,
    undefined_glslang_or_spvtools: usize,
}

/// Reads `DT_NEEDED` and the undefined dynamic symbols of a little-endian ELF shared library.
fn parse_dynamic(bytes: &[u8]) -> Result<Dynamic, String> {
    if bytes.len() < 64 || &bytes[..4] != b"\x7fELF" {
        return Err("not an ELF file (a linker script?)".into());
    }
    let is64 = match bytes[4] {
        1 => false,
        2 => true,
        _ => return Err("unknown ELF class".into()),
    };
    if bytes[5] != 1 {
        return Err("not little-endian ELF".into());
    }
    let r = Reader { bytes };
    let (shoff, shentsize, shnum) = if is64 {
        (r.u64(0x28)?, r.u16(0x3a)? as usize, r.u16(0x3c)? as usize)
    } else {
        (
            r.u32(0x20)? as u64,
            r.u16(0x2e)? as usize,
            r.u16(0x30)? as usize,
        )
    };
    let shoff = usize::try_from(shoff).map_err(|_| "bad section offset")?;
    // (type, offset, size, link, entsize) of each section.
    let mut sections = Vec::with_capacity(shnum);
    for i in 0..shnum {
        let h = shoff + i * shentsize;
        sections.push(if is64 {
            (
                r.u32(h + 4)?,
                r.u64(h + 0x18)?,
                r.u64(h + 0x20)?,
                r.u32(h + 0x28)?,
                r.u64(h + 0x38)?,
            )
        } else {
            let w = |o| r.u32(h + o).map(u64::from);
            (
                r.u32(h + 4)?,
                w(0x10)?,
                w(0x14)?,
                r.u32(h + 0x18)?,
                w(0x24)?,
            )
        });
    }
    let strtab = |link: u32| -> Result<&[u8], String> {
        let &(_, off, size, _, _) = sections.get(link as usize).ok_or("bad sh_link")?;
        r.slice(off, size)
    };
    const SHT_DYNAMIC: u32 = 6;
    const SHT_DYNSYM: u32 = 11;
    const DT_NEEDED: u64 = 1;
    let mut dynamic = Dynamic {
        needed: Vec::new(),
        undefined_glslang_or_spvtools: 0,
    };
    let mut saw_dynsym = false;
    for &(kind, off, size, link, entsize) in &sections {
        if kind == SHT_DYNAMIC {
            let strings = strtab(link)?;
            let entry = if is64 { 16 } else { 8 };
            let table = r.slice(off, size)?;
            for e in table.chunks_exact(entry) {
                let e = Reader { bytes: e };
                let (tag, val) = if is64 {
                    (e.u64(0)?, e.u64(8)?)
                } else {
                    (e.u32(0)? as u64, e.u32(4)? as u64)
                };
                if tag == DT_NEEDED {
                    dynamic.needed.push(c_str(strings, val)?);
                }
            }
        } else if kind == SHT_DYNSYM {
            saw_dynsym = true;
            let strings = strtab(link)?;
            let entry = if entsize > 0 {
                entsize as usize
            } else if is64 {
                24
            } else {
                16
            };
            let table = r.slice(off, size)?;
            for s in table.chunks_exact(entry) {
                let s = Reader { bytes: s };
                let (name, shndx) = if is64 {
                    (s.u32(0)?, s.u16(6)?)
                } else {
                    (s.u32(0)?, s.u16(14)?)
                };
                if shndx != 0 || name == 0 {
                    continue;
                }
                let name = c_str(strings, name as u64)?;
                // Itanium-mangled names in namespace glslang or spvtools (`_ZN7glslang...`,
                // `_ZNK8spvtools...`), and SPIRV-Tools' C API (`spvContextCreate`, ...).
                if name.contains("7glslang")
                    || name.contains("8spvtools")
                    || name.starts_with("spv")
                {
                    dynamic.undefined_glslang_or_spvtools += 1;
                }
            }
        }
    }
    if !saw_dynsym {
        return Err("no dynamic symbol table".into());
    }
    Ok(dynamic)
}

fn c_str(strings: &[u8], offset: u64) -> Result<String, String> {
    let rest = strings.get(offset as usize..).ok_or("bad string offset")?;
    let end = rest
        .iter()
        .position(|&b| b == 0)
        .ok_or("unterminated string")?;
    Ok(String::from_utf8_lossy(&rest[..end]).into_owned())
}

struct Reader<'a> {
    bytes: &'a [u8],
}

impl<'a> Reader<'a> {
    fn slice(&self, offset: u64, len: u64) -> Result<&'a [u8], String> {
        let start = usize::try_from(offset).map_err(|_| "offset out of range")?;
        let len = usize::try_from(len).map_err(|_| "length out of range")?;
        self.bytes
            .get(start..start.checked_add(len).ok_or("length out of range")?)
            .ok_or_else(|| "truncated ELF file".to_string())
    }
    fn array<const N: usize>(&self, offset: usize) -> Result<[u8; N], String> {
        Ok(self.slice(offset as u64, N as u64)?.try_into().unwrap())
    }
    fn u16(&self, offset: usize) -> Result<u16, String> {
        self.array(offset).map(u16::from_le_bytes)
    }
    fn u32(&self, offset: usize) -> Result<u32, String> {
        self.array(offset).map(u32::from_le_bytes)
    }
    fn u64(&self, offset: usize) -> Result<u64, String> {
        self.array(offset).map(u64::from_le_bytes)
    }
}
