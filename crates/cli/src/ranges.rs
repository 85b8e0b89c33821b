//! The ranges of numeric options, checked while the command line is parsed: a number out of
//! range is a usage error naming the option (exit 2) before any file is read or any memory
//! is sized from it.

fn int_in(s: &str, lo: usize, hi: usize) -> Result<usize, String> {
    let v: usize = s
        .trim()
        .parse()
        .map_err(|_| format!("not a whole number from {lo} to {hi}"))?;
    if (lo..=hi).contains(&v) {
        Ok(v)
    } else {
        Err(format!("must be from {lo} to {hi}"))
    }
}

/// A finite number above `lo` (`open`) or of at least `lo`.
fn float_from(s: &str, lo: f64, open: bool) -> Result<f64, String> {
    let bound = if open {
        format!("must be a finite number above {lo}")
    } else {
        format!("must be a finite number of {lo} or more")
    };
    let v: f64 = s.trim().parse().map_err(|_| bound.clone())?;
    // NaN fails every comparison.
    let above = if open { v > lo } else { v >= lo };
    if above && v.is_finite() {
        Ok(v)
    } else {
        Err(bound)
    }
}

/// `--max-gap`: 1 frame or more (more frames than the trial has means no limit).
pub fn max_gap(s: &str) -> Result<usize, String> {
    int_in(s, 1, usize::MAX)
}

/// `--gap-lengths`: each 1 to [`repair::evaluate::MAX_GAP_LENGTH`] frames.
pub fn gap_length(s: &str) -> Result<usize, String> {
    int_in(s, 1, repair::evaluate::MAX_GAP_LENGTH)
}

/// `--gaps-per-length`: 1 to [`repair::evaluate::MAX_GAPS_PER_LENGTH`].
pub fn gaps_per_length(s: &str) -> Result<usize, String> {
    int_in(s, 1, repair::evaluate::MAX_GAPS_PER_LENGTH)
}

/// Most frames `keyframes --max-segment` takes (a gap longer than the motion is no limit).
pub const MAX_SEGMENT: usize = u32::MAX as usize;

/// `keyframes --max-segment`: 0 (no limit) to [`MAX_SEGMENT`] frames.
pub fn max_segment(s: &str) -> Result<usize, String> {
    int_in(s, 0, MAX_SEGMENT)
}

/// `keyframes --max-error`: an RMS distance from 0 to [`bvh::keyframes::MAX_ABS_VALUE`], the
/// largest value a motion may hold.
pub fn keyframe_error(s: &str) -> Result<f64, String> {
    let hi = bvh::keyframes::MAX_ABS_VALUE;
    match float_from(s, 0.0, false) {
        Ok(v) if v <= hi => Ok(v),
        _ => Err(format!("must be a finite number from 0 to {hi:e}")),
    }
}

/// A length such as `--spike-min-mm` or `--tolerance`: finite, 0 or more.
pub fn non_negative(s: &str) -> Result<f64, String> {
    float_from(s, 0.0, false)
}

/// `convert --scale`: finite and above 0 (how fine or coarse it may be depends on the data,
/// and is checked against them).
pub fn scale(s: &str) -> Result<f32, String> {
    let v = float_from(s, 0.0, true)? as f32;
    if v > 0.0 && v.is_finite() {
        Ok(v)
    } else {
        Err(format!(
            "must be from {} to {}",
            f32::MIN_POSITIVE,
            f32::MAX
        ))
    }
}

/// A choice the library names and parses (`FromStr` with the library's error: an event
/// source, a side, a fill method …), checked while the command line is parsed, so a
/// misspelt name is a usage error (exit 2) before any file is read, said with this tool's
/// flags.
pub fn choice<T>(s: &str) -> Result<T, String>
where
    T: std::str::FromStr,
    T::Err: Into<c3dfix::Error>,
{
    s.parse::<T>().map_err(|e| crate::flags::phrase(&e.into()))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn bounds_hold() {
        let jobs = choice::<c3dfix::Jobs>;
        assert_eq!(jobs("4").map(c3dfix::Jobs::get), Ok(Some(4)));
        assert!(jobs("0").is_err() && jobs("257").is_err() && jobs("-1").is_err());
        assert_eq!(
            jobs("18446744073709551615").unwrap_err(),
            "--jobs 18446744073709551615: must be from 1 to 256"
        );
        assert!(gap_length("18446744073709551615").is_err());
        assert!(gaps_per_length("18446744073709551615").is_err());
        assert_eq!(max_gap("18446744073709551615"), Ok(usize::MAX));
        assert!(max_gap("0").is_err());
        assert_eq!(non_negative("0"), Ok(0.0));
        for bad in ["-1", "nan", "inf", "1e400", "x"] {
            assert!(non_negative(bad).is_err(), "{bad}");
            assert!(scale(bad).is_err(), "{bad}");
        }
        assert!(scale("0").is_err());
        assert_eq!(scale("1e30"), Ok(1e30));
        assert_eq!(max_segment("0"), Ok(0));
        assert_eq!(max_segment("4294967295"), Ok(4294967295));
        assert!(max_segment("18446744073709551615")
            .unwrap_err()
            .contains("from 0 to 4294967295"));
        assert_eq!(keyframe_error("1e9"), Ok(1e9));
        for bad in ["-1", "nan", "inf", "1e300", "x"] {
            assert!(keyframe_error(bad).is_err(), "{bad}");
        }
    }
}
