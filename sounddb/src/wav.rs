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
        // 16-bit PCM (every pack's units) read straight from the data chunk: hound's
        // per-sample iterator was 12 % of a render's start-up; the values are the same.
        hound::SampleFormat::Int if spec.bits_per_sample == 16 => {
            // `WavReader::new` reads the header unbuffered: the cursor is at the data.
            let start = reader.into_inner().position() as usize;
            let data = &bytes[start.min(bytes.len())..];
            let n = (data.len() / 2).min(declared);
            let scale = 1.0 / f64::from(1u32 << 15);
            data.chunks_exact(2)
                .take(n)
                .map(|b| (f64::from(i16::from_le_bytes([b[0], b[1]])) * scale) as f32)
                .collect()
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

    #[test]
    fn the_16_bit_fast_path_reads_what_hound_reads() {
        // Mono and stereo, with a chunk after the data (hound's writer adds none: append one).
        for channels in [1u16, 2] {
            let spec = hound::WavSpec {
                channels,
                sample_rate: 48_000,
                bits_per_sample: 16,
                sample_format: hound::SampleFormat::Int,
            };
            let mut cur = Cursor::new(Vec::new());
            {
                let mut w = hound::WavWriter::new(&mut cur, spec).unwrap();
                for i in 0..999i32 * i32::from(channels) {
                    w.write_sample(((i * 7919) % 65_536 - 32_768) as i16)
                        .unwrap();
                }
                w.finalize().unwrap();
            }
            let bytes = cur.into_inner();
            let want: Vec<i32> = hound::WavReader::new(Cursor::new(&bytes[..]))
                .unwrap()
                .into_samples::<i32>()
                .map(|s| s.unwrap())
                .collect();
            let d = decode(&bytes).unwrap();
            assert_eq!(d.samples.len(), 999);
            for (k, got) in d.samples.iter().enumerate() {
                let c = usize::from(channels);
                let frame = &want[k * c..(k + 1) * c];
                let expect = frame
                    .iter()
                    .map(|&v| (f64::from(v) / 32_768.0) as f32)
                    .sum::<f32>()
                    / c as f32;
                assert_eq!(got.to_bits(), expect.to_bits(), "sample {k}");
            }
            let mut tail = bytes.clone();
            tail.extend_from_slice(b"LIST\x04\0\0\0abcd");
            assert_eq!(decode(&tail).unwrap().samples, d.samples);
        }
    }
}
