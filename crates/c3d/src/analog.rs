//! Analog data: raw values as stored, and the calibration that turns them into physical units.

use serde::Serialize;

/// Analog samples, sample-major: sample `s` (0 .. frames × samples_per_frame) of channel `c`
/// is at `s * channels + c`. Values are as stored (integers widened to f32, exactly).
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Analog {
    pub(crate) channels: usize,
    pub(crate) samples_per_frame: usize,
    pub(crate) frames: usize,
    pub raw: Vec<f32>,
}

impl Analog {
    pub fn new(frames: usize, channels: usize, samples_per_frame: usize) -> Analog {
        Analog {
            channels,
            samples_per_frame,
            frames,
            raw: vec![0.0; frames * channels * samples_per_frame],
        }
    }

    pub fn channels(&self) -> usize {
        self.channels
    }

    pub fn samples_per_frame(&self) -> usize {
        self.samples_per_frame
    }

    /// Number of analog samples per channel.
    pub fn samples(&self) -> usize {
        self.frames * self.samples_per_frame
    }

    /// One channel's raw values.
    pub fn channel_raw(&self, c: usize) -> Vec<f32> {
        self.raw
            .iter()
            .skip(c)
            .step_by(self.channels.max(1))
            .copied()
            .collect()
    }
}

/// How raw analog values become physical ones:
/// `(raw − offset[c]) × scale[c] × gen_scale` (the C3D manual's formula).
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Calibration {
    pub scale: Vec<f32>,
    pub offset: Vec<f32>,
    pub gen_scale: f32,
    /// ANALOG:FORMAT is "UNSIGNED": raw integers (and offsets) are read as 0..65535.
    pub unsigned: bool,
}

impl Calibration {
    #[inline]
    pub fn physical(&self, c: usize, raw: f32) -> f32 {
        let off = self.offset.get(c).copied().unwrap_or(0.0);
        let sc = self.scale.get(c).copied().unwrap_or(1.0);
        (raw - off) * sc * self.gen_scale
    }

    /// All of `analog` in physical units, laid out like `analog.raw`.
    pub fn apply(&self, analog: &Analog) -> Vec<f32> {
        let ch = analog.channels.max(1);
        analog
            .raw
            .iter()
            .enumerate()
            .map(|(i, &r)| self.physical(i % ch, r))
            .collect()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn physical_units_follow_the_manual() {
        let cal = Calibration {
            scale: vec![0.5, 2.0],
            offset: vec![10.0, -3.0],
            gen_scale: 0.1,
            unsigned: false,
        };
        assert!((cal.physical(0, 30.0) - 1.0).abs() < 1e-6);
        assert!((cal.physical(1, 2.0) - 1.0).abs() < 1e-6);
        let a = Analog {
            channels: 2,
            samples_per_frame: 1,
            frames: 1,
            raw: vec![30.0, 2.0],
        };
        assert_eq!(a.channel_raw(1), vec![2.0]);
        let phys = cal.apply(&a);
        assert!((phys[0] - 1.0).abs() < 1e-6 && (phys[1] - 1.0).abs() < 1e-6);
    }
}
