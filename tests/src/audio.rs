//! WAV reading and simple signal checks for the tests.

use std::path::Path;

/// A stereo float WAV: (sample rate, left, right).
pub fn read_stereo(path: &Path) -> (u32, Vec<f32>, Vec<f32>) {
    let mut r = hound::WavReader::open(path)
        .unwrap_or_else(|e| panic!("cannot open {}: {e}", path.display()));
    let spec = r.spec();
    assert_eq!(spec.channels, 2, "{} is not stereo", path.display());
    assert_eq!(spec.sample_format, hound::SampleFormat::Float);
    let s: Vec<f32> = r.samples::<f32>().map(|x| x.expect("sample")).collect();
    let left = s.iter().step_by(2).copied().collect();
    let right = s.iter().skip(1).step_by(2).copied().collect();
    (spec.sample_rate, left, right)
}

/// True if every sample is finite and not subnormal.
pub fn all_finite_normal(x: &[f32]) -> bool {
    x.iter()
        .all(|v| v.is_finite() && (*v == 0.0 || v.is_normal()))
}

/// Largest absolute sample.
pub fn peak(x: &[f32]) -> f32 {
    x.iter().fold(0.0f32, |m, v| m.max(v.abs()))
}
