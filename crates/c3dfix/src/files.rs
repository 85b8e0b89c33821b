//! Path in, path out: one file repaired or converted with the checks, refusals and atomic
//! writes of `c3dfix repair` and `c3dfix convert`. The command and the Python package
//! (`c3dfix.repair_file`, `c3dfix.convert_file`) both call these functions, so the same
//! options give the same bytes by construction.
//!
//! Every destination is checked before the work: an existing file is replaced only when asked
//! (`force`, or `in_place`), a device, FIFO or folder never; a report never lands on the input
//! or the output. The outputs of one call (the file, its backup, the report) are written
//! together by [`save::write_all`], all or nothing.

use crate::error::{Conflict, Error, Result};
use crate::options::RepairOptions;
use crate::repair::{repair_configured, Repaired};
use crate::save::{
    self, check_destination, new_backup, refuse_input, refuse_own_input, replacing, write_all,
};
use crate::trial::open_mapped;
use serde::Serialize;
use std::path::{Path, PathBuf};

/// Where one input goes.
#[derive(Debug, Clone, Default, PartialEq, Eq)]
pub struct Destination {
    /// The file to write; with `in_place`, none (the input is replaced).
    pub output: Option<PathBuf>,
    /// Replace the input itself (atomically).
    pub in_place: bool,
    /// With `in_place`: keep the original first as `FILE.bak` (an existing backup is kept as
    /// it is, being the true original).
    pub backup: bool,
    /// Replace an existing output (and report).
    pub force: bool,
}

impl Destination {
    /// The path written for `input`, once the options are known to go together.
    pub fn path(&self, input: &Path) -> Result<PathBuf> {
        if self.backup && !self.in_place {
            return Err(Error::Conflict(Conflict::BackupWithoutInPlace));
        }
        match (&self.output, self.in_place) {
            (Some(_), true) => Err(Error::Conflict(Conflict::OutputAndInPlace)),
            (Some(o), false) => Ok(o.clone()),
            (None, true) => Ok(input.to_path_buf()),
            (None, false) => Err(Error::Conflict(Conflict::NoDestination)),
        }
    }

    /// Whether an existing file at the output may be replaced.
    fn overwrite(&self) -> bool {
        self.force || self.in_place
    }
}

/// Repair `input` as `opts` says and write it to `dest` (and the full report, as JSON, to
/// `report` when given): what `c3dfix repair` and each file of `c3dfix batch` do, and
/// Python's `repair_file`. The summary names the output and the backup, if one was made;
/// [`Repaired::report`] is the report written. In place, a rerun that changes nothing
/// leaves the file alone (not even its time stamp, nor a backup) and says `unchanged`:
/// `batch --in-place` run twice touches no file the second time.
pub fn repair(
    input: &Path,
    dest: &Destination,
    opts: &RepairOptions,
    report: Option<&Path>,
) -> Result<Repaired> {
    let out = dest.path(input)?;
    if !dest.in_place {
        refuse_own_input(input, &out)?;
    }
    // The options are checked once, before any file is touched.
    let cfg = opts.config()?;
    let overwrite = dest.overwrite();
    check_destination(&out, overwrite)?;
    if let Some(r) = report {
        refuse_input(r, &[input, &out], "the report")?;
        check_destination(r, dest.force)?;
    }
    let backup = if dest.backup { new_backup(input) } else { None };
    let mut c = open_mapped(input)?;
    let mut done = repair_configured(&mut c, opts, cfg, input)?;
    done.summary.output = out.display().to_string();
    done.summary.backup = backup.as_ref().map(|b| b.display().to_string());
    let text = match report {
        Some(_) => serde_json::to_string_pretty(&done.report())
            .map_err(|e| Error::Output(format!("cannot encode the report: {e}")))?,
        None => String::new(),
    };
    let bytes = c.encoded().map_err(|source| Error::C3d {
        path: input.to_path_buf(),
        source,
    })?;
    let unchanged = c.source_bytes() == Some(&bytes[..]) && save::same_file(input, &out);
    // With a backup (in place), the input as it is on disk: the trial in memory holds the
    // repaired samples.
    let mut outs = if unchanged {
        done.summary.unchanged = true;
        done.summary.backup = None;
        Vec::new()
    } else {
        replacing(&out, &bytes, overwrite, backup.as_deref())
    };
    if let Some(path) = report {
        outs.push(save::Output {
            path,
            bytes: save::Content::Bytes(text.as_bytes()),
            replace: dest.force,
        });
    }
    write_all(&outs)?;
    Ok(done)
}

/// The formats a conversion asks for; `None` keeps each file's own.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct Conversion {
    pub processor: Option<c3d::Processor>,
    pub format: Option<c3d::NumberFormat>,
    /// POINT:SCALE for integer output (default: kept if exact, else the finest that fits).
    pub scale: Option<f32>,
}

impl Conversion {
    /// The options read from their names, as the command and the Python package take them:
    /// processor `intel`, `dec` or `sgi`; format `int` or `float`; scale above 0 and finite.
    pub fn parse(
        processor: Option<&str>,
        format: Option<&str>,
        scale: Option<f64>,
    ) -> Result<Self> {
        let processor = processor
            .map(|p| {
                c3d::Processor::parse_name(p).ok_or_else(|| {
                    Error::options(format!("unknown processor {p:?}: intel, dec or sgi"))
                })
            })
            .transpose()?;
        let format = format
            .map(|f| match f.to_ascii_lowercase().as_str() {
                "int" | "integer" => Ok(c3d::NumberFormat::Integer),
                "float" | "real" => Ok(c3d::NumberFormat::Float),
                _ => Err(Error::options(format!(
                    "unknown format {f:?}: int or float"
                ))),
            })
            .transpose()?;
        let scale = scale
            .map(|s| {
                let v = s as f32;
                if v > 0.0 && v.is_finite() {
                    Ok(v)
                } else {
                    Err(Error::options(format!(
                        "scale {s} must be from {} to {}",
                        f32::MIN_POSITIVE,
                        f32::MAX
                    )))
                }
            })
            .transpose()?;
        Ok(Conversion {
            processor,
            format,
            scale,
        })
    }
}

/// What converting one file did.
#[derive(Debug, Clone, Serialize, PartialEq)]
pub struct Converted {
    pub output: String,
    pub processor: &'static str,
    pub format: &'static str,
    pub bytes: usize,
    /// In place: the file already was what was asked for, byte for byte, and was not rewritten.
    pub unchanged: bool,
    /// What the reader noticed about the input (format rule breaks it read around).
    pub warnings: Vec<String>,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub backup: Option<String>,
}

/// Convert `input` as `want` says and write it to `dest`: what `c3dfix convert` does for
/// one file. In place, a file that would not change is left alone (not even its time stamp
/// moves).
pub fn convert(input: &Path, dest: &Destination, want: &Conversion) -> Result<Converted> {
    let out = dest.path(input)?;
    convert_to(
        input,
        &out,
        want,
        dest.in_place,
        dest.backup,
        dest.overwrite(),
    )
}

/// [`convert`] with the output already resolved (the command's `--out-dir` names it per
/// file): `overwrite` allows replacing an existing output, `backup` keeps the file at the
/// output first as `FILE.bak`.
pub fn convert_to(
    input: &Path,
    output: &Path,
    want: &Conversion,
    in_place: bool,
    backup: bool,
    overwrite: bool,
) -> Result<Converted> {
    if !in_place {
        refuse_own_input(input, output)?;
    }
    let c = open_mapped(input)?;
    let processor = want.processor.unwrap_or(c.processor());
    let format = want.format.unwrap_or(c.format());
    let bytes = c
        .converted(processor, format, want.scale)
        .map_err(|source| Error::C3d {
            path: input.to_path_buf(),
            source,
        })?;
    let mut done = Converted {
        output: output.display().to_string(),
        processor: processor.name(),
        format: format.name(),
        bytes: bytes.len(),
        unchanged: false,
        warnings: c.warnings().iter().map(|w| w.to_string()).collect(),
        backup: None,
    };
    if in_place && c.source_bytes() == Some(&bytes[..]) {
        done.unchanged = true;
        return Ok(done);
    }
    // Only a change of number format can lose values (integers round to POINT:SCALE): a
    // change of processor keeps every value of every corpus file (`c3d`'s diff test), and
    // the check decodes both files, which a long trial should not pay for nothing.
    if format != c.format() && c.source_bytes() != Some(&bytes[..]) {
        done.warnings.extend(values_not_held(&c, &bytes));
    }
    check_destination(output, overwrite)?;
    // In place the output is the file itself (by its canonical path, so a backup of a file
    // reached through a link sits beside the file, as `crate::save()` puts it).
    let backup_to = if backup && output.exists() {
        new_backup(output)
    } else {
        None
    };
    done.backup = backup_to.as_ref().map(|b| b.display().to_string());
    let outs = replacing(output, &bytes, overwrite, backup_to.as_deref());
    // The backup and the converted file land together, or neither does.
    write_all(&outs)?;
    Ok(done)
}

/// What the converted `bytes` do not hold of `c` as stored, read back and compared as data
/// (`c3d::diff::DiffOptions::data`): an integer target rounds coordinates to POINT:SCALE and
/// residuals to its steps, analog values to whole words. Said, not refused: the user asked
/// for the target, and the message says by how much.
fn values_not_held(c: &c3d::C3d, bytes: &[u8]) -> Vec<String> {
    let Ok(back) = c3d::read(bytes.to_vec()) else {
        return vec!["the converted file could not be read back to check its values".into()];
    };
    let opts = c3d::diff::DiffOptions {
        tolerance: 0.0,
        data: true,
    };
    let d = c3d::diff::diff_with(c, &back, &opts);
    let mut out = Vec::new();
    let m = &d.points.markers;
    if !m.is_empty() {
        let moved = m.iter().map(|x| x.max_displacement).fold(0.0, f64::max);
        let frames: usize = m.iter().map(|x| x.frames_changed).sum();
        out.push(format!(
            "the target cannot hold every point as stored: {frames} samples of {} points changed (coordinates by up to {moved:.3e} {}, or their residual)",
            m.len(),
            c.point_units()
        ));
    }
    let a = &d.analog.channels;
    if !a.is_empty() {
        let most = a.iter().map(|x| x.max_difference).fold(0.0, f64::max);
        out.push(format!(
            "the target cannot hold every analog value as stored: {} channels changed by up to {most:.3e}",
            a.len()
        ));
    }
    if !d.parameters.is_empty() || !d.header.is_empty() {
        let names: Vec<String> = d
            .header
            .iter()
            .map(|f| f.field.clone())
            .chain(d.parameters.iter().map(|p| p.name.clone()))
            .collect();
        out.push(format!(
            "the target does not hold as stored: {}",
            names.join(", ")
        ));
    }
    out
}
