//! Thinning long series for drawing without changing what the eye sees: per pixel column only
//! the lowest and highest sample are kept, so a 100 000-frame trial draws the same envelope as
//! every sample would, in a file a few hundred kilobytes long. The data itself is never altered.

/// Polylines through the valid samples of `values` (sample `i` at x = `x0 + i * dx`), at most
/// about two points per column of `columns`. Invalid or non-finite samples break the line.
pub fn polylines(
    x0: f64,
    dx: f64,
    values: &[f32],
    valid: &[bool],
    columns: usize,
) -> Vec<Vec<(f64, f64)>> {
    let n = values.len().min(valid.len());
    let ok = |i: usize| valid[i] && values[i].is_finite();
    let pt = |i: usize| (x0 + i as f64 * dx, values[i] as f64);
    let mut out = Vec::new();
    let mut line = Vec::new();
    let columns = columns.max(1);
    if n <= 2 * columns {
        for i in 0..n {
            if ok(i) {
                line.push(pt(i));
            } else if !line.is_empty() {
                out.push(std::mem::take(&mut line));
            }
        }
    } else {
        let per = n as f64 / columns as f64;
        let mut i = 0;
        while i < n {
            let col = (i as f64 / per) as usize;
            let end = (((col + 1) as f64 * per).ceil() as usize).clamp(i + 1, n);
            let mut j = i;
            while j < end {
                if !ok(j) {
                    if !line.is_empty() {
                        out.push(std::mem::take(&mut line));
                    }
                    j += 1;
                    continue;
                }
                // One run of valid samples inside this column: its extremes, in time order.
                let (mut lo, mut hi, mut k) = (j, j, j);
                while k < end && ok(k) {
                    if values[k] < values[lo] {
                        lo = k;
                    }
                    if values[k] > values[hi] {
                        hi = k;
                    }
                    k += 1;
                }
                let (a, b) = if lo <= hi { (lo, hi) } else { (hi, lo) };
                line.push(pt(a));
                if b != a {
                    line.push(pt(b));
                }
                j = k;
            }
            i = end;
        }
    }
    if !line.is_empty() {
        out.push(line);
    }
    out
}

/// Runs of `true` in `flags` as `(first, last)` indices, runs closer than one column merged so
/// that shading never needs more rectangles than there are pixels.
pub fn spans(flags: &[bool], columns: usize) -> Vec<(usize, usize)> {
    let join = flags.len() / columns.max(1);
    let mut out: Vec<(usize, usize)> = Vec::new();
    let mut start = None;
    for (i, &f) in flags.iter().chain([false].iter()).enumerate() {
        match (f, start) {
            (true, None) => start = Some(i),
            (false, Some(s)) => {
                match out.last_mut() {
                    Some(last) if s < last.1 + 1 + join => last.1 = i - 1,
                    _ => out.push((s, i - 1)),
                }
                start = None;
            }
            _ => {}
        }
    }
    out
}

/// At most one of the sorted sample indices per pixel column, for point marks.
pub fn thin(indices: &[usize], n: usize, columns: usize) -> Vec<usize> {
    let per = (n as f64 / columns.max(1) as f64).max(1.0);
    let mut out = Vec::new();
    let mut last_col = None;
    for &i in indices {
        let col = (i as f64 / per) as usize;
        if last_col != Some(col) {
            out.push(i);
            last_col = Some(col);
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn short_series_are_drawn_as_they_are_and_gaps_break_lines() {
        let v = [1.0, 2.0, 3.0, 4.0, 5.0];
        let ok = [true, true, false, true, true];
        let l = polylines(0.0, 0.5, &v, &ok, 100);
        assert_eq!(
            l,
            vec![vec![(0.0, 1.0), (0.5, 2.0)], vec![(1.5, 4.0), (2.0, 5.0)]]
        );
    }

    #[test]
    fn long_series_keep_the_extremes_of_each_column() {
        let n = 100_000;
        let v: Vec<f32> = (0..n).map(|i| ((i * 7919) % 1000) as f32).collect();
        let ok = vec![true; n];
        let l = polylines(0.0, 1.0, &v, &ok, 500);
        let pts: usize = l.iter().map(|p| p.len()).sum();
        assert!(pts <= 1000, "{pts}");
        let max = l.iter().flatten().map(|p| p.1).fold(f64::MIN, f64::max);
        let min = l.iter().flatten().map(|p| p.1).fold(f64::MAX, f64::min);
        assert_eq!((min, max), (0.0, 999.0));
    }

    #[test]
    fn spans_merge_when_closer_than_a_column() {
        let f = [false, true, true, false, true, false, false, false, true];
        assert_eq!(spans(&f, 100), vec![(1, 2), (4, 4), (8, 8)]);
        assert_eq!(spans(&f, 3), vec![(1, 4), (8, 8)]);
        assert_eq!(thin(&[0, 1, 2, 50, 51], 100, 10), vec![0, 50]);
    }
}
