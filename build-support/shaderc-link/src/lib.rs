//! Completes the link of shaderc on distributions whose `libshaderc.so` does not record its
//! glslang and SPIRV-Tools dependencies (Debian 12's `libshaderc1` 2023.2-1 is one).
//!
//! The crate has no items. It exists for its build script, which runs before any crate that
//! depends on it is linked:
//!
//! - `shaderc-sys` (the `shaderc` crate's native half) finds the distribution's `libshaderc.so`
//!   with pkg-config and links it with `-l dylib=shaderc`. Debian's library leaves about forty
//!   `glslang::` and `spvtools::` symbols undefined without a `DT_NEEDED` entry for the
//!   libraries that define them, and Debian ships those libraries only as static archives
//!   (`libMachineIndependent.a`, `libSPIRV-Tools.a`, ... from `glslang-dev` and
//!   `spirv-tools`). So every program that uses shaderc there, such as the build script of
//!   motion-shadows, fails to link ("undefined reference: glslang::TShader::...").
//! - This crate's build script looks at the library `shaderc-sys` will pick (it repeats
//!   shaderc-sys's search: `SHADERC_LIB_DIR`, `VULKAN_SDK`, pkg-config `shaderc`, then the
//!   multiarch directory). Only when that is a `libshaderc.so` that is ELF, has undefined
//!   glslang/SPIRV-Tools symbols and names no glslang/SPIRV library in `DT_NEEDED`, and
//!   `libshaderc_combined.a`, `libglslang.a` and `libSPIRV-Tools.a` lie beside it, does it emit
//!   `cargo:rustc-link-search` and `cargo:rustc-link-lib=static:-bundle=...` for shaderc's
//!   static library and glslang's and SPIRV-Tools' archives, then `dylib=stdc++`. rustc puts
//!   static libraries before shared ones on the link line, so the program takes shaderc from
//!   the archive and `libshaderc.so` is dropped (`--as-needed`). Completing the shared library
//!   instead links but crashes on Debian 12: it embeds the SPIR-V back end of an older glslang
//!   than `glslang-dev`'s.
//! - Cargo attaches these arguments to this crate, so they reach the link of every program
//!   that loads it, a build script included, in this repository or in a crate that depends on
//!   motion-shadows by path or git. A `.cargo/config.toml` override of the `shaderc` links key
//!   cannot do that: cargo reads it only for builds started below its directory.
//! - Anywhere else (other operating systems, a `libshaderc.so` that links, `SHADERC_LIB_DIR`
//!   or `VULKAN_SDK` set, no `libshaderc.so`) it emits nothing.
//!
//! Set `MOTION_SHADOWS_SHADERC_LINK=off` to make it emit nothing in any case, for instance
//! together with shaderc's `build-from-source` feature on a machine that has Debian's broken
//! package installed, or when you link shaderc your own way.
//!
//! rustc links the native libraries of the crates a program loads, and it does not load a
//! dependency the code never names, so the dependent names this crate once: motion-shadows'
//! build script has `use motion_shadows_shaderc_link as _;`. Being a build-dependency alone
//! is not enough (the link then fails as before).
#![no_std]
