//! The Rust side of the layout check: each mirror flattened into scalars by offset, from
//! `offset_of!` and `size_of` of the struct itself, so the description cannot drift from it.
//! [`mirror!`] lists a struct's fields by name only (their types come from the struct), and
//! destructures it without `..`, so a field added to the struct and not listed here fails to
//! compile.

use super::spirv_structs::{Leaf, Scalar};
use crate::technique::gpu_types::{
    CameraParams, Counters, DrawRecord, GpuCameraEnd, GpuLight, GpuLightEnd, LongListHeader, Node,
    PlainMapHeader, Range, ShadowMapHeader, TriangleRecord,
};
use crate::technique::push_constants::{
    DrawPush, GBufferPush, LightingRasterPush, MapDrawPush, MapPush, MaskPush, RadiancePush,
    RasterCamera, RasterPush, ShadePush, TsmMaskPush,
};
use glam::{Mat4, UVec4, Vec4};

/// A type a mirror's field may have: it appends its scalars at `at`, named `name`.
pub trait Flatten {
    fn flatten(at: u32, name: &str, out: &mut Vec<Leaf>);
}

macro_rules! scalar {
    ($ty:ty, $scalar:expr) => {
        impl Flatten for $ty {
            fn flatten(at: u32, name: &str, out: &mut Vec<Leaf>) {
                out.push(Leaf {
                    offset: at,
                    scalar: $scalar,
                    name: name.to_owned(),
                });
            }
        }
    };
}

scalar!(f32, Scalar::F32);
scalar!(u32, Scalar::U32);
scalar!(i32, Scalar::I32);
scalar!(u64, Scalar::U64);

impl<T: Flatten, const N: usize> Flatten for [T; N] {
    fn flatten(at: u32, name: &str, out: &mut Vec<Leaf>) {
        for i in 0..N {
            T::flatten(at + (i * size_of::<T>()) as u32, name, out);
        }
    }
}

impl Flatten for Vec4 {
    fn flatten(at: u32, name: &str, out: &mut Vec<Leaf>) {
        <[f32; 4]>::flatten(at, name, out);
    }
}

impl Flatten for UVec4 {
    fn flatten(at: u32, name: &str, out: &mut Vec<Leaf>) {
        <[u32; 4]>::flatten(at, name, out);
    }
}

impl Flatten for Mat4 {
    fn flatten(at: u32, name: &str, out: &mut Vec<Leaf>) {
        // Column-major, as GLSL's mat4 (glam's `to_cols_array` order).
        <[[f32; 4]; 4]>::flatten(at, name, out);
    }
}

/// The field `f` of `S` flattened at `at` (its type inferred from the accessor).
fn field<S, F: Flatten>(_: fn(&S) -> &F, at: u32, name: &str, out: &mut Vec<Leaf>) {
    F::flatten(at, name, out);
}

/// `impl Flatten` for a mirror from its fields' names.
macro_rules! mirror {
    ($ty:ident { $($field:ident),* $(,)? }) => {
        impl Flatten for $ty {
            fn flatten(at: u32, _: &str, out: &mut Vec<Leaf>) {
                // Every field is listed: this pattern has no `..`.
                let _every_field_listed = |v: &$ty| {
                    let $ty { $($field: _),* } = v;
                };
                $(field(
                    |s: &$ty| &s.$field,
                    at + std::mem::offset_of!($ty, $field) as u32,
                    stringify!($field),
                    out,
                );)*
            }
        }
    };
    // A struct whose GLSL counterpart ends before `$tail`, which the shaders read as a struct
    // of its own at that offset (checked on its own, and its offset by a test).
    ($ty:ident { $($field:ident),* $(,)? } tail $tail:ident) => {
        impl Flatten for $ty {
            fn flatten(at: u32, _: &str, out: &mut Vec<Leaf>) {
                let _every_field_listed = |v: &$ty| {
                    let $ty { $($field: _,)* $tail: _ } = v;
                };
                $(field(
                    |s: &$ty| &s.$field,
                    at + std::mem::offset_of!($ty, $field) as u32,
                    stringify!($field),
                    out,
                );)*
            }
        }
    };
}

mirror!(GpuLight {
    view,
    proj,
    position,
    direction,
    emission,
    bias
});
mirror!(ShadowMapHeader {
    light,
    size,
    range_heads,
    ranges,
    coverage,
    cover_depth,
    heads,
    nodes,
    counters,
    long_pixels,
    nearest,
    static_nearest,
    tiles,
    list_ranges,
    triangles,
    static_names,
} tail light_end);
mirror!(GpuLightEnd {
    view,
    frame,
    position,
    direction
});
mirror!(PlainMapHeader {
    light,
    size,
    depths,
    ids
});
mirror!(Counters {
    node_count,
    node_capacity,
    range_count,
    range_capacity,
    overlong_pixels,
    longest_list,
    ranges_without_coverage,
    invalid_triangles,
    wrapped,
    ranges_direct,
    sorted_count,
    static_names,
});
mirror!(LongListHeader { count, groups });
mirror!(DrawRecord {
    positions0,
    positions1,
    indices,
    stride0,
    stride1,
    index_kind,
    vertex_count,
    first_id,
    triangle_count,
    albedo_flags,
    model0,
    model1,
});
mirror!(Node {
    depth,
    time,
    id,
    next
});
mirror!(Range {
    t_s,
    t_e,
    d_s,
    d_e,
    id,
    next
});
mirror!(CameraParams {
    view_proj,
    position,
    forward,
    ray00,
    ray_dx,
    ray_dy,
    image,
    shading,
    visibility,
    radiance,
    counters,
    camera_end,
});
mirror!(GpuCameraEnd { frame, position });
mirror!(TriangleRecord { at0, at1 });
mirror!(DrawPush {
    draws,
    draw_index,
    draw_count
});
mirror!(MapDrawPush {
    draw,
    map,
    time,
    flags
});
mirror!(MapPush { map });
mirror!(LightingRasterPush {
    draw,
    visibility,
    target,
    first_sample,
    sample_count,
    time,
    flags,
});
mirror!(RasterCamera {
    origin,
    near,
    far,
    ray00,
    ray_dx,
    ray_dy,
    width,
    spp,
    seed
});
mirror!(RasterPush {
    pass,
    camera,
    padding
});
mirror!(ShadePush {
    draws,
    shadow,
    target,
    draw_count,
    first_sample,
    time,
    flags
});
mirror!(MaskPush {
    inv_view_proj,
    map,
    size,
    background_depth,
    flags,
    over_budget,
    loop_budget,
    time,
    queue,
    round,
    rounds,
    capacity,
    probe,
});
mirror!(TsmMaskPush {
    inv_view_proj,
    light,
    size,
    background_depth,
    flags,
    map_size,
    time,
    maps,
    inv_maps,
    first_map,
    batch,
    reserved,
});
mirror!(GBufferPush {
    view_proj,
    eye,
    draws,
    draw_index,
    time
});
mirror!(RadiancePush { radiance, size });

/// `T` flattened, by offset.
pub fn leaves<T: Flatten>() -> Vec<Leaf> {
    let mut out = Vec::new();
    T::flatten(0, "", &mut out);
    out.sort_by_key(|l| l.offset);
    out
}
