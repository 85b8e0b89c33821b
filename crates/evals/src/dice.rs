//! The benchmarks' own dice (xorshift64*): the same sequence on every machine and every run,
//! so a benchmark's cut fragments, ghosts and splits are the same wherever it is re-measured.

/// xorshift64* from a seed (any but 0).
pub struct Dice(pub u64);

impl Dice {
    pub fn draw(&mut self) -> u64 {
        self.0 ^= self.0 >> 12;
        self.0 ^= self.0 << 25;
        self.0 ^= self.0 >> 27;
        self.0.wrapping_mul(0x2545_f491_4f6c_dd1d)
    }

    /// Uniform in `lo..=hi` (`lo` when `hi` is below it).
    pub fn int(&mut self, lo: usize, hi: usize) -> usize {
        lo + (self.draw() % (hi.max(lo) - lo + 1) as u64) as usize
    }

    /// Uniform in `lo..hi`.
    pub fn real(&mut self, lo: f64, hi: f64) -> f64 {
        lo + (hi - lo) * (self.draw() >> 11) as f64 / (1u64 << 53) as f64
    }

    /// A direction uniform on the unit sphere.
    pub fn direction(&mut self) -> [f64; 3] {
        loop {
            let v = [
                self.real(-1.0, 1.0),
                self.real(-1.0, 1.0),
                self.real(-1.0, 1.0),
            ];
            let n = (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]).sqrt();
            if n > 0.1 && n <= 1.0 {
                return v.map(|c| c / n);
            }
        }
    }
}
