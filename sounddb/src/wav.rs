//! WAV decoding to mono f32 and encoding of 16-bit mono units (hound).

use std::io::Cursor;

/// A decoded WAV file.
pub struct Decoded {
    /// Mono samples in [-1, 1] (channels averaged).
    pub samples: Vec<f32>,
    /// Sample rate, Hz.
    pub sample_rate_hz: u32,
    /// Channel count of the file.
    pub channels: u16,
}

/// Decodes a WAV byte string. Truncated files are errors (hound reports the short read).
pub fn decode(bytes: &[u8]) -> Result<Decoded, String> {
    let reader = hound::WavReader::new(Cursor::new(bytes)).map_err(|e| e.to_string())?;
    let spec = reader.spec();
    if spec.channels == 0 {
        return Err("zero channels".into());
    }
    let declared = reader.len() as usize;
    let channels = spec.channels as usize;
    let interleaved: Vec<f32> = match spec.sample_format {
        hound::SampleFormat::Float => {
            if spec.bits_per_sample != 32 {
                return Err(format!(
                    "{}-bit float is not supported",
                    spec.bits_per_sample
                ));
            }
            reader
                .into_samples::<f32>()
                .collect::<Result<_, _>>()
                .map_err(|e| e.to_string())?
        }
        hound::SampleFormat::Int => {
            let bits = spec.bits_per_sample;
            if !(8..=32).contains(&bits) {
                return Err(format!("{bits}-bit PCM is not supported"));
            }
            let scale = 1.0 / (1u64 << (bits - 1)) as f64;
            reader
                .into_samples::<i32>()
                .map(|s| s.map(|v| (f64::from(v) * scale) as f32))
                .collect::<Result<_, _>>()
                .map_err(|e| e.to_string())?
        }
    };
    if interleaved.len() != declared || !interleaved.len().is_multiple_of(channels) {
        return Err(format!(
            "truncated: header declares {declared} samples, {} present",
            interleaved.len()
        ));
    }
    let samples = if channels == 1 {
        interleaved
    } else {
        interleaved
            .chunks_exact(channels)
            .map(|f| f.iter().sum::<f32>() / channels as f32)
            .collect()
    };
    Ok(Decoded {
        samples,
        sample_rate_hz: spec.sample_rate,
        channels: spec.channels,
    })
}

/// Encodes mono samples as a 16-bit PCM WAV (values clamped to [-1, 1], rounded).
pub fn encode_i16(samples: &[f32], sample_rate_hz: u32) -> Vec<u8> {
    let spec = hound::WavSpec {
        channels: 1,
        sample_rate: sample_rate_hz,
        bits_per_sample: 16,
        sample_format: hound::SampleFormat::Int,
    };
    let mut bytes = Vec::with_capacity(44 + 2 * samples.len());
    {
        let mut w = hound::WavWriter::new(Cursor::new(&mut bytes), spec)
            .expect("writing a WAV header to memory cannot fail");
        for &s in samples {
            let v = (s.clamp(-1.0, 1.0) * 32767.0).round() as i16;
            w.write_sample(v).expect("writing to memory cannot fail");
        }
        w.finalize()
            .expect("finalizing a WAV in memory cannot fail");
    }
    bytes
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn round_trip_and_truncated() {
        let x: Vec<f32> = (0..1000).map(|i| ((i as f32) * 0.01).sin() * 0.5).collect();
        let bytes = encode_i16(&x, 44_100);
        let d = decode(&bytes).unwrap();
        assert_eq!(d.sample_rate_hz, 44_100);
        assert_eq!(d.samples.len(), 1000);
        for (a, b) in x.iter().zip(&d.samples) {
            assert!((a - b).abs() < 1.0 / 32767.0);
        }
        let cut = &bytes[..bytes.len() - 101];
        assert!(decode(cut).is_err());
        assert!(decode(b"RIFF....WAVEjunk").is_err());
        assert!(decode(&[]).is_err());
    }
}
