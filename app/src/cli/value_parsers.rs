//! The value parsers of options several commands share (`--shadow-size`, `--exposure`),
//! re-exported from [`super::args`].

/// Parses "WxH".
pub fn parse_size(text: &str) -> Result<(u32, u32), String> {
    let (w, h) = text
        .split_once(['x', 'X'])
        .ok_or_else(|| format!("expected WxH (e.g. 1024x768), got {text:?}"))?;
    let parse = |s: &str| {
        s.trim()
            .parse::<u32>()
            .map_err(|e| format!("{s:?} in {text:?}: {e}"))
    };
    Ok((parse(w)?, parse(h)?))
}

/// Largest |exposure| in stops. 2^64 ~ 1.8e19: beyond it every radiance a scene can produce
/// (f32, albedo <= 1, finite intensities) maps to all black or all white, so such a value is
/// a mistake, as are NaN and infinities (which would also print `null` in `--json`).
pub const MAX_EXPOSURE_STOPS: f32 = 64.0;

/// Parses `--exposure`: a finite number of stops in [-64, 64].
pub fn parse_exposure(text: &str) -> Result<f32, String> {
    let stops: f32 = text
        .trim()
        .parse()
        .map_err(|e| format!("{e} (expected a number of stops)"))?;
    if stops.is_finite() && stops.abs() <= MAX_EXPOSURE_STOPS {
        Ok(stops)
    } else {
        Err(format!(
            "must be a finite number of stops in [-{MAX_EXPOSURE_STOPS}, {MAX_EXPOSURE_STOPS}]"
        ))
    }
}
