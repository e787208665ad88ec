//! Times of shadow maps and reference slices: stratified over the shutter, deterministic for
//! a seed.

/// SplitMix64: a tiny, well-mixed generator; enough for a few thousand jitters.
fn splitmix(state: &mut u64) -> u64 {
    *state = state.wrapping_add(0x9e37_79b9_7f4a_7c15);
    let mut z = *state;
    z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
    z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
    z ^ (z >> 31)
}

/// `count` times, the i-th uniformly random in [i/count, (i+1)/count). `salt` separates
/// uses (time-dependent maps, reference slices) that share a seed.
pub fn stratified_times(count: u32, seed: u32, salt: u64) -> Vec<f32> {
    let mut state = ((seed as u64) << 32) ^ salt;
    (0..count)
        .map(|i| {
            let jitter = (splitmix(&mut state) >> 40) as f64 / (1u64 << 24) as f64;
            ((i as f64 + jitter) / count as f64) as f32
        })
        .collect()
}

/// Salt of the time-dependent shadow maps' times.
pub const TSM_SALT: u64 = 0x7453_4d00;
/// Salt of the reference's slice times.
pub const REFERENCE_SALT: u64 = 0x5265_6600;

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn one_time_per_stratum_and_deterministic() {
        let t = stratified_times(64, 3, TSM_SALT);
        assert_eq!(t.len(), 64);
        for (i, &v) in t.iter().enumerate() {
            assert!(
                v >= i as f32 / 64.0 && v < (i + 1) as f32 / 64.0,
                "{i}: {v}"
            );
        }
        assert_eq!(t, stratified_times(64, 3, TSM_SALT));
        assert_ne!(t, stratified_times(64, 4, TSM_SALT));
        assert_ne!(t, stratified_times(64, 3, REFERENCE_SALT));
    }
}
