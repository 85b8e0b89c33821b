//! The lab's vertical, found from the data: labs are Z-up or Y-up (some X-up), and a file
//! rarely says which. The pelvis stands about a leg's length above the feet whatever the
//! lab, so the vertical is the axis along which the pelvis is farthest from the heels on
//! average, pointing from the heels to the pelvis.

/// An axis of the lab and its direction (+1 or −1).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Vertical {
    pub axis: usize,
    pub sign: f64,
}

impl Vertical {
    /// Height of `p` along the vertical.
    pub fn height(self, p: [f64; 3]) -> f64 {
        self.sign * p[self.axis]
    }

    /// `p` with its vertical component set to zero.
    pub fn horizontal(self, p: [f64; 3]) -> [f64; 3] {
        let mut h = p;
        h[self.axis] = 0.0;
        h
    }
}

/// The vertical from the pelvis and the feet (NaN where missing); `None` when no frame has
/// both.
pub fn vertical(pelvis: &[[f64; 3]], feet: &[&[[f64; 3]]]) -> Option<Vertical> {
    let mut sum = [0.0; 3];
    let mut n = 0usize;
    for foot in feet {
        for (p, f) in pelvis.iter().zip(foot.iter()) {
            let d = [p[0] - f[0], p[1] - f[1], p[2] - f[2]];
            if d.iter().all(|v| v.is_finite()) {
                for k in 0..3 {
                    sum[k] += d[k];
                }
                n += 1;
            }
        }
    }
    if n == 0 {
        return None;
    }
    let axis = (0..3).max_by(|&a, &b| sum[a].abs().total_cmp(&sum[b].abs()))?;
    Some(Vertical {
        axis,
        sign: if sum[axis] < 0.0 { -1.0 } else { 1.0 },
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn y_up_and_z_down() {
        let pelvis = vec![[0.0, 900.0, 10.0]; 3];
        let heel = vec![[100.0, 50.0, 0.0]; 3];
        assert_eq!(
            vertical(&pelvis, &[&heel]),
            Some(Vertical { axis: 1, sign: 1.0 })
        );
        let pelvis = vec![[0.0, 0.0, -900.0]; 3];
        let heel = vec![
            [f64::NAN, 0.0, -50.0],
            [300.0, 0.0, -50.0],
            [0.0, 0.0, -40.0],
        ];
        assert_eq!(
            vertical(&pelvis, &[&heel]),
            Some(Vertical {
                axis: 2,
                sign: -1.0
            })
        );
        assert_eq!(vertical(&pelvis, &[&[[f64::NAN; 3]; 3]]), None);
    }
}
