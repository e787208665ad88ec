//! Reading accessors into plain arrays. The gltf crate's own readers slice and unwrap on
//! trust (a short buffer, a zero count or a mismatched component type panics there), so a
//! scene file naming a broken model would abort the program; every bound is checked here
//! instead and reported as an error.

use gltf::accessor::{Accessor, DataType, Dimensions};

use super::super::limits::MAX_GLTF_ACCESSOR_VALUES;

/// One component of an element: the raw value and, for normalised integers, its float.
fn component(bytes: &[u8], ty: DataType, normalized: bool) -> f32 {
    match ty {
        DataType::F32 => f32::from_le_bytes([bytes[0], bytes[1], bytes[2], bytes[3]]),
        DataType::U32 => u32::from_le_bytes([bytes[0], bytes[1], bytes[2], bytes[3]]) as f32,
        DataType::U16 => {
            let v = f32::from(u16::from_le_bytes([bytes[0], bytes[1]]));
            if normalized { v / 65535.0 } else { v }
        }
        DataType::I16 => {
            let v = f32::from(i16::from_le_bytes([bytes[0], bytes[1]]));
            if normalized {
                (v / 32767.0).max(-1.0)
            } else {
                v
            }
        }
        DataType::U8 => {
            let v = f32::from(bytes[0]);
            if normalized { v / 255.0 } else { v }
        }
        DataType::I8 => {
            let v = f32::from(bytes[0] as i8);
            if normalized { (v / 127.0).max(-1.0) } else { v }
        }
    }
}

fn integer(bytes: &[u8], ty: DataType) -> Option<u32> {
    match ty {
        DataType::U8 => Some(u32::from(bytes[0])),
        DataType::U16 => Some(u32::from(u16::from_le_bytes([bytes[0], bytes[1]]))),
        DataType::U32 => Some(u32::from_le_bytes([bytes[0], bytes[1], bytes[2], bytes[3]])),
        _ => None,
    }
}

/// The bytes of `count` elements of `element` bytes each, `stride` apart, starting `offset`
/// bytes into the view; checked against the view and the buffer's actual data.
fn strided<'b>(
    view: &gltf::buffer::View,
    buffers: &'b [Vec<u8>],
    offset: usize,
    count: usize,
    element: usize,
    stride: usize,
) -> Result<&'b [u8], String> {
    let data = buffers
        .get(view.buffer().index())
        .ok_or_else(|| format!("buffer {} does not exist", view.buffer().index()))?;
    let view_end = view.offset().checked_add(view.length());
    let view_bytes = view_end
        .and_then(|end| data.get(view.offset()..end))
        .ok_or_else(|| {
            format!(
                "bufferView {} (bytes {}..+{}) runs past the end of buffer {} ({} bytes)",
                view.index(),
                view.offset(),
                view.length(),
                view.buffer().index(),
                data.len()
            )
        })?;
    if count == 0 {
        return Ok(&[]);
    }
    let needed = (count - 1)
        .checked_mul(stride)
        .and_then(|n| n.checked_add(element))
        .and_then(|n| n.checked_add(offset));
    match needed {
        Some(end) if end <= view_bytes.len() => Ok(&view_bytes[offset..end]),
        _ => Err(format!(
            "{count} elements of {element} bytes (stride {stride}) from byte {offset} do not fit \
             in bufferView {} ({} bytes)",
            view.index(),
            view_bytes.len()
        )),
    }
}

/// All components of `accessor` as f32 (normalised integers mapped to [0, 1] or [-1, 1]),
/// sparse substitutions applied; `count * dims` values. `what` names the accessor's role in
/// errors; `allowed` lists the element shapes that role accepts.
pub(super) fn read_floats(
    accessor: &Accessor,
    buffers: &[Vec<u8>],
    what: &str,
    allowed: &[Dimensions],
) -> Result<Vec<f32>, String> {
    read(accessor, buffers, what, allowed, |bytes, ty, norm| {
        Ok(component(bytes, ty, norm))
    })
}

/// Integer components (indices, joint numbers): unsigned types only, not normalised.
pub(super) fn read_integers(
    accessor: &Accessor,
    buffers: &[Vec<u8>],
    what: &str,
    allowed: &[Dimensions],
) -> Result<Vec<u32>, String> {
    if accessor.normalized() {
        return Err(format!(
            "{what}: accessor {} is normalized",
            accessor.index()
        ));
    }
    read(accessor, buffers, what, allowed, |bytes, ty, _| {
        integer(bytes, ty).ok_or_else(|| format!("component type {ty:?} is not unsigned"))
    })
}

fn read<T: Copy + Default>(
    accessor: &Accessor,
    buffers: &[Vec<u8>],
    what: &str,
    allowed: &[Dimensions],
    decode: impl Fn(&[u8], DataType, bool) -> Result<T, String>,
) -> Result<Vec<T>, String> {
    let context = |m: String| format!("{what} (accessor {}): {m}", accessor.index());
    let dims = accessor.dimensions();
    if !allowed.contains(&dims) {
        return Err(context(format!(
            "type {dims:?}, expected one of {allowed:?}"
        )));
    }
    // Matrices of 1- and 2-byte components carry column padding; no role read here uses
    // them (inverse bind matrices are float MAT4).
    if matches!(dims, Dimensions::Mat2 | Dimensions::Mat3) {
        return Err(context("MAT2/MAT3 accessors are not supported".into()));
    }
    let ty = accessor.data_type();
    let size = ty.size();
    let n = dims.multiplicity();
    let count = accessor.count();
    let values = count
        .checked_mul(n)
        .filter(|&v| v as u64 <= MAX_GLTF_ACCESSOR_VALUES)
        .ok_or_else(|| context(format!("count {count} is over the loader's limit")))?;
    let mut out = vec![T::default(); values];
    let element = size * n;
    let decode_into = |out: &mut [T], bytes: &[u8]| -> Result<(), String> {
        for (slot, c) in out.iter_mut().zip(bytes.chunks_exact(size)) {
            *slot = decode(c, ty, accessor.normalized()).map_err(&context)?;
        }
        Ok(())
    };
    // No bufferView: all zeros (sparse values may then replace some).
    if let Some(view) = accessor.view() {
        let stride = view.stride().unwrap_or(element);
        if stride < element {
            return Err(context(format!(
                "byteStride {stride} < element size {element}"
            )));
        }
        let bytes =
            strided(&view, buffers, accessor.offset(), count, element, stride).map_err(&context)?;
        for (i, chunk) in out.chunks_exact_mut(n).enumerate() {
            let start = i * stride;
            decode_into(chunk, &bytes[start..start + element])?;
        }
    }
    if let Some(sparse) = accessor.sparse() {
        let k = sparse.count();
        let ind = sparse.indices();
        let index_size = ind.index_type().size();
        let index_bytes = strided(
            &ind.view(),
            buffers,
            ind.offset(),
            k,
            index_size,
            index_size,
        )
        .map_err(&context)?;
        let vals = sparse.values();
        let value_bytes =
            strided(&vals.view(), buffers, vals.offset(), k, element, element).map_err(&context)?;
        for j in 0..k {
            let raw = &index_bytes[j * index_size..(j + 1) * index_size];
            let index = match index_size {
                1 => usize::from(raw[0]),
                2 => usize::from(u16::from_le_bytes([raw[0], raw[1]])),
                _ => u32::from_le_bytes([raw[0], raw[1], raw[2], raw[3]]) as usize,
            };
            if index >= count {
                return Err(context(format!(
                    "sparse index {index} out of range (count {count})"
                )));
            }
            let at = j * element;
            decode_into(
                &mut out[index * n..(index + 1) * n],
                &value_bytes[at..at + element],
            )?;
        }
    }
    Ok(out)
}
