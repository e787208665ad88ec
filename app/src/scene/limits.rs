//! The sizes a scene may have, checked before anything of that size is read or built
//! (documented in docs/scene-format.md, "Limits"). Each bound is derived below from what a
//! device can hold, so a scene inside them can be rendered somewhere and one outside them is
//! refused in milliseconds instead of exhausting memory.

/// Bytes of the library's vertex record (`SceneVertex`: two `vec4` positions).
pub const VERTEX_BYTES: u64 = 32;

/// Largest scene file read, and largest OBJ model. 256 MiB of JSON holds ~10 million
/// explicit vertices, more than any sensible hand-written or exported scene; files larger
/// than this (or endless streams such as `/dev/zero`) are refused, never read to the end.
pub const MAX_SCENE_FILE_BYTES: u64 = 256 << 20;
/// See [`MAX_SCENE_FILE_BYTES`]; OBJ text of 256 MiB holds ~10 million triangles.
pub const MAX_OBJ_BYTES: u64 = 256 << 20;

/// Largest glTF model (JSON or GLB) and largest buffer it refers to, for the reason given
/// at [`MAX_SCENE_FILE_BYTES`].
pub const MAX_GLTF_BYTES: u64 = 256 << 20;
/// Most values (elements x components) one glTF accessor may hold: an accessor without a
/// buffer view (all zeros, possibly sparse) has no data bounding its count, so this bounds
/// the memory it takes (2^27 f32 = 512 MiB).
pub const MAX_GLTF_ACCESSOR_VALUES: u64 = 1 << 27;
/// Most levels of midpoint subdivision of a glTF model: each multiplies the triangles by 4,
/// and 8 levels turn even a single triangle into 65,536; the scene's triangle limit still
/// applies to the result.
pub const MAX_GLTF_SUBDIVIDE: u32 = 8;

/// Most triangles one scene may have: 2^25 = 33,554,432, whose vertex buffer takes
/// 2^25 x 3 x 32 B = 3 GiB. No Vulkan device can go much further: a shader reaches the vertex
/// buffer through a storage-buffer descriptor, whose range (`maxStorageBufferRange`) is a
/// 32-bit byte count, so 4 GiB - 1 (44.7 million triangles) is the ceiling on every device.
/// The device's own limit (128 MiB on lavapipe, ~1.4 million triangles) still decides at
/// render time; this bound only turns absurd sizes away before gigabytes are built.
pub const MAX_SCENE_TRIANGLES: u64 = 1 << 25;

/// Most quads along each side of a tessellated box or plane face. A box at this limit has
/// 12 x 256^2 = 786,432 triangles, a 72 MiB vertex buffer: inside the 128 MiB that the
/// Vulkan specification guarantees every device's `maxStorageBufferRange` to reach, so one
/// such box renders on any device (1024, the old limit, needed 1.2 GB, more than most).
pub const MAX_SUBDIVISIONS: u32 = 256;

/// Scene names become output file names (`<name>-<method>.png`): 1 to 64 characters of
/// `[A-Za-z0-9._-]`, not starting with `.` (no hidden files, no `..`, no path separators).
pub const MAX_NAME_CHARS: usize = 64;

/// Largest |coordinate| over the camera's near distance. Positions are single precision
/// (relative rounding 2^-24 ~ 6e-8), so at magnitude X every position and every ray test
/// result is off by ~6e-8 X. At X = 1e5 x near that is 0.6% of the near distance, the
/// smallest distance the scene says it resolves, so shapes at that scale keep their form.
/// Far beyond it the image breaks outright. Measured on lavapipe with the probe (a
/// floor triangle with corners at +-X seen from 7 units away, 48x36): exact up to X = 2e6
/// with near 0.1 (2e7 x near), black from X = 4e6 (4e7 x near); with near 0.01, black from
/// X = 3e6. The bound keeps a margin of 200 below the smallest failing ratio measured.
pub const MAX_COORDINATE_OVER_NEAR: f32 = 1e5;

/// `random-cubes`: edge length range of a cube. Below 0.1 the scene's framing (its camera
/// near plane never goes under 0.1) would clip the whole field; above 1000 the field's
/// light and ground grow past what single precision frames well.
pub const CUBE_SIZE_RANGE: (f32, f32) = (0.1, 1000.0);
/// `random-cubes`: largest displacement of a cube over the shutter.
pub const MAX_CUBE_SPEED: f32 = 1000.0;

/// Longest piece of user text (a name, a path, a parser message) quoted in an error.
pub const MAX_QUOTED_CHARS: usize = 200;
/// Every scene error message is at most this long (user text is clipped to fit).
pub const MAX_ERROR_CHARS: usize = 1024;
