//! [`C3d`]: a whole file as a model — header, parameters, point and analog data — plus the
//! bytes it was read from, so that writing it back changes only what was changed.

use crate::analog::{Analog, Calibration};
use crate::data::{DecodeAnalog, DecodePoints, Layout, Patch, PointsView, Scan, ScanNotes};
use crate::error::Warning;
use crate::error::{Error, Result};
use crate::events::{self, Event};
use crate::header::{Header, HeaderEvent};
use crate::parameters::Parameters;
use crate::points::Points;
use crate::processor::Processor;
use serde::Serialize;
use std::borrow::Cow;
use std::sync::OnceLock;

/// Integer or floating-point data.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
#[serde(rename_all = "lowercase")]
pub enum NumberFormat {
    Integer,
    Float,
}

impl NumberFormat {
    pub fn name(self) -> &'static str {
        match self {
            NumberFormat::Integer => "integer",
            NumberFormat::Float => "float",
        }
    }
}

/// What was read, kept for lossless rewriting.
#[derive(Debug, Clone)]
pub(crate) struct Source {
    /// The file's bytes as read, with any samples patched in by [`C3d::patch_points`].
    pub bytes: crate::memory::Bytes,
    pub header: Header,
    pub processor: Processor,
    pub param_start: usize,
    /// End of the bytes the parameter records used (at least the declared section).
    pub param_end: usize,
    pub data_offset: usize,
    pub layout: Layout,
}

/// A C3D file.
///
/// `header` and `parameters` are public: edit them freely; the writer compares them with what
/// was read and re-encodes only what differs. Point and analog data are reached through
/// [`C3d::points_mut`] / [`C3d::analog_mut`], which mark them for re-encoding; even then only
/// samples whose values changed get new bytes.
///
/// A file that was read keeps one copy of its data: its bytes. Point and analog arrays are
/// decoded from them the first time they are asked for, so that commands which only scan
/// the data ([`C3d::map_point_chunks`]), patch a few markers ([`C3d::patch_points`]) or
/// rewrite the file unchanged ([`C3d::encoded`]) never hold a second copy of a long trial.
#[derive(Debug, Clone)]
pub struct C3d {
    pub header: Header,
    pub parameters: Parameters,
    points: OnceLock<Points>,
    analog: OnceLock<Analog>,
    layout: Layout,
    processor: Processor,
    warnings: Vec<Warning>,
    pub(crate) source: Option<Source>,
    pub(crate) points_dirty: bool,
    pub(crate) analog_dirty: bool,
}

impl C3d {
    #[allow(clippy::too_many_arguments)]
    pub(crate) fn from_parts(
        header: Header,
        parameters: Parameters,
        layout: Layout,
        processor: Processor,
        warnings: Vec<Warning>,
        source: Source,
    ) -> C3d {
        C3d {
            header,
            parameters,
            points: OnceLock::new(),
            analog: OnceLock::new(),
            layout,
            processor,
            warnings,
            source: Some(source),
            points_dirty: false,
            analog_dirty: false,
        }
    }

    /// A new file in memory (no source bytes): write it with [`C3d::to_bytes`].
    ///
    /// `scale` is POINT:SCALE: negative for float data, positive for int16 data scaled by it.
    pub fn new(
        points: Points,
        analog: Analog,
        parameters: Parameters,
        processor: Processor,
        scale: f32,
    ) -> C3d {
        let layout = Layout {
            points: points.count,
            analog_channels: analog.channels,
            analog_samples_per_frame: analog.samples_per_frame.max(1),
            frames: points.frames,
            float: scale < 0.0,
            unsigned_analog: false,
            point_scale: scale.abs(),
        };
        let mut header = Header::new();
        header.scale = scale;
        C3d {
            header,
            parameters,
            points: OnceLock::from(points),
            analog: OnceLock::from(analog),
            layout,
            processor,
            warnings: Vec::new(),
            source: None,
            points_dirty: true,
            analog_dirty: true,
        }
    }

    /// The point data, decoded from the file's bytes on first use.
    pub fn points(&self) -> &Points {
        self.points.get_or_init(|| match self.data_bytes() {
            Some(bytes) => self.processor.dispatch(DecodePoints {
                bytes,
                layout: self.layout,
            }),
            None => Points::new(self.layout.frames, self.layout.points),
        })
    }

    /// The point data if it has been decoded (or was given).
    pub(crate) fn decoded_points(&self) -> Option<&Points> {
        self.points.get()
    }

    /// Mutable point data; samples changed through it are re-encoded when writing.
    pub fn points_mut(&mut self) -> &mut Points {
        self.points();
        self.points_dirty = true;
        self.points
            .get_mut()
            .expect("the points were decoded just above")
    }

    /// The analog data, decoded from the file's bytes on first use.
    pub fn analog(&self) -> &Analog {
        self.analog.get_or_init(|| match self.data_bytes() {
            Some(bytes) => self.processor.dispatch(DecodeAnalog {
                bytes,
                layout: self.layout,
            }),
            None => Analog::new(
                self.layout.frames,
                self.layout.analog_channels,
                self.layout.analog_samples_per_frame,
            ),
        })
    }

    /// Mutable analog data (raw values); changed samples are re-encoded when writing.
    pub fn analog_mut(&mut self) -> &mut Analog {
        self.analog();
        self.analog_dirty = true;
        self.analog
            .get_mut()
            .expect("the analog data were decoded just above")
    }

    /// The stored data section of a file that was read (`layout.data_bytes()` long).
    fn data_bytes(&self) -> Option<&[u8]> {
        let src = self.source.as_ref()?;
        let need = src.layout.data_bytes();
        Some(
            src.bytes
                .get(src.data_offset..src.data_offset + need)
                .unwrap_or(&[]),
        )
    }

    /// Number of frames, without decoding anything.
    pub fn frames(&self) -> usize {
        self.points.get().map_or(self.layout.frames, |p| p.frames)
    }

    /// Number of points per frame, without decoding anything.
    pub fn point_count(&self) -> usize {
        self.points.get().map_or(self.layout.points, |p| p.count)
    }

    /// Number of analog channels, without decoding anything.
    pub fn analog_channels(&self) -> usize {
        self.analog
            .get()
            .map_or(self.layout.analog_channels, |a| a.channels)
    }

    /// Frames per chunk of [`C3d::map_point_chunks`]: chunk `i` starts at frame
    /// `i * point_chunk_frames()`.
    pub fn point_chunk_frames(&self) -> usize {
        crate::data::chunk_frames(&self.layout)
    }

    /// Number of chunks [`C3d::map_point_chunks`] visits (none when there are no points, however
    /// many frames the header claims).
    pub fn point_chunks(&self) -> usize {
        if self.point_count() == 0 {
            return 0;
        }
        self.frames().div_ceil(self.point_chunk_frames())
    }

    /// The point samples of the frames at `indices` (0-based; those past the trial's end left
    /// missing), as a small [`Points`]: read from the decoded arrays when there are, else
    /// decoded from the file's bytes, so a test that reads a few frames of a long trial needs
    /// no copy of it.
    pub fn point_frames(&self, indices: &[usize]) -> Points {
        let count = self.layout.points;
        let mut out = Points::new(indices.len(), count);
        let view = match (self.points.get(), self.data_bytes()) {
            (None, Some(bytes)) => {
                let whole = (self.layout.frames * self.layout.frame_bytes()).min(bytes.len());
                PointsView::stored(0, &bytes[..whole], self.layout, self.processor)
            }
            (p, _) => {
                let p = p.unwrap_or_else(|| self.points());
                PointsView::decoded(0, p, 0..p.frames * p.count)
            }
        };
        for (i, &f) in indices.iter().enumerate() {
            if f >= view.frames {
                continue;
            }
            for point in 0..count.min(view.count) {
                let (xyz, residual, cameras) = view.sample(f, point);
                let k = out.index(i, point);
                out.xyz[k] = xyz;
                out.residual[k] = residual;
                out.camera_mask[k] = cameras;
            }
        }
        out
    }

    /// Run `f` on the point data chunk by chunk (runs of [`C3d::point_chunk_frames`] whole
    /// frames), in parallel, each call with its own `state` (`states[i]` goes with chunk `i`;
    /// chunks without a state are not visited). The results come back in frame order.
    ///
    /// When the points have not been decoded, each chunk's samples are decoded from the file's
    /// bytes as they are asked for, so scanning a long trial needs no second copy of it; the
    /// samples are the ones [`C3d::points`] would give.
    pub fn map_point_chunks<S, R, F>(&self, states: Vec<S>, f: F) -> Vec<R>
    where
        S: Send,
        R: Send,
        F: Fn(S, PointsView<'_>) -> R + Sync,
    {
        use rayon::prelude::*;
        let chunk = self.point_chunk_frames();
        let visit = |(i, s): (usize, S)| {
            let first = i * chunk;
            let view = match (self.points.get(), self.data_bytes()) {
                (None, Some(bytes)) => {
                    let fb = self.layout.frame_bytes();
                    let end = ((first + chunk) * fb).min(self.layout.frames * fb);
                    PointsView::stored(first, &bytes[first * fb..end], self.layout, self.processor)
                }
                (p, _) => {
                    let p = p.unwrap_or_else(|| self.points());
                    let end = (first + chunk).min(p.frames) * p.count;
                    PointsView::decoded(first, p, first * p.count..end)
                }
            };
            f(s, view)
        };
        let n = self.point_chunks().min(states.len());
        let states = states.into_iter().take(n).enumerate();
        if self.layout.data_bytes() > crate::data::PARALLEL_SCAN_BYTES {
            let states: Vec<_> = states.collect();
            forkpool::install(|| states.into_par_iter().map(visit).collect())
        } else {
            states.map(visit).collect()
        }
    }

    /// What one pass over the stored samples notes (see [`crate::data::Scan`]).
    pub(crate) fn scan(&self) -> ScanNotes {
        match self.data_bytes() {
            Some(bytes) => self.processor.dispatch(Scan {
                bytes,
                layout: self.layout,
            }),
            None => ScanNotes::default(),
        }
    }

    /// Set point samples: each `(frame, point, xyz, residual, camera_mask)` (0-based frame
    /// and point). Returns how many were given.
    ///
    /// Until the points are decoded, the samples are encoded straight into the file's bytes
    /// (as [`C3d::points_mut`] would when writing: only samples whose values change get new
    /// bytes), so a repair of a long trial holds no decoded copy of it. Afterwards, or when the
    /// file's data section overlaps its header or parameters (a damaged file, written afresh),
    /// they go into the decoded points.
    pub fn patch_points(
        &mut self,
        samples: impl IntoIterator<Item = (usize, usize, [f32; 3], f32, u8)>,
    ) -> Result<usize> {
        let patchable = self.points.get().is_none()
            && self.source.as_ref().is_some_and(|src| {
                let data = src.data_offset..src.data_offset + src.layout.data_bytes();
                let clear = |r: std::ops::Range<usize>| r.end <= data.start || data.end <= r.start;
                data.end <= src.bytes.len()
                    && clear(0..crate::header::BLOCK)
                    && clear(src.param_start..src.param_end)
            });
        if patchable {
            if let Some(src) = self.source.as_mut() {
                let range = src.data_offset..src.data_offset + src.layout.data_bytes();
                return src.processor.dispatch(Patch {
                    out: &mut src.bytes[range],
                    layout: src.layout,
                    samples: samples.into_iter(),
                });
            }
        }
        let p = self.points_mut();
        let (frames, count) = (p.frames, p.count);
        let mut n = 0;
        for (f, i, xyz, r, m) in samples {
            if f >= frames || i >= count {
                return Err(Error::Misuse(format!(
                    "sample (frame {f}, point {i}) outside {frames} frames × {count} points"
                )));
            }
            let k = f * count + i;
            p.xyz[k] = xyz;
            p.residual[k] = r;
            p.camera_mask[k] = m;
            n += 1;
        }
        Ok(n)
    }

    /// Whether nothing was changed since reading: the bytes would be written back as read.
    fn unchanged(&self, src: &Source) -> bool {
        !self.points_dirty
            && !self.analog_dirty
            && self.header == src.header
            && self.parameters.unchanged(src.processor)
    }

    /// The file's bytes, borrowed from what was read when nothing changed (so saving an
    /// unchanged long trial copies nothing), else encoded as [`C3d::to_bytes`] does.
    pub fn encoded(&self) -> Result<Cow<'_, [u8]>> {
        match &self.source {
            Some(src) if self.unchanged(src) => Ok(Cow::Borrowed(&src.bytes)),
            _ => self.to_bytes().map(Cow::Owned),
        }
    }

    pub fn layout(&self) -> &Layout {
        &self.layout
    }

    pub fn processor(&self) -> Processor {
        self.processor
    }

    pub fn format(&self) -> NumberFormat {
        if self.layout.float {
            NumberFormat::Float
        } else {
            NumberFormat::Integer
        }
    }

    pub(crate) fn set_warnings(&mut self, warnings: Vec<Warning>) {
        self.warnings = warnings;
    }

    /// What in the file broke the rules but could be read around.
    pub fn warnings(&self) -> &[Warning] {
        &self.warnings
    }

    /// The bytes the file was read from, if it was read.
    pub fn source_bytes(&self) -> Option<&[u8]> {
        self.source.as_ref().map(|s| &s.bytes[..])
    }

    /// Where the data section starts in the bytes the file was read from (after the reader's
    /// checks of the header against POINT:DATA_START), if it was read.
    pub fn data_offset(&self) -> Option<usize> {
        self.source.as_ref().map(|s| s.data_offset)
    }

    /// The parameter `group:name` (case-insensitive), e.g. `c.param("POINT", "RATE")`; its
    /// typed views are [`Parameter::as_f32s`](crate::Parameter::as_f32s), `as_i32s`,
    /// `as_u16s` and `as_strings`.
    pub fn param(&self, group: &str, name: &str) -> Option<&crate::parameters::Parameter> {
        self.parameters.get(group, name)
    }

    /// Point labels (POINT:LABELS, LABELS2, …), one per stored point; missing ones are
    /// named by their number so every point has a label.
    pub fn point_labels(&self) -> Vec<String> {
        self.labels("POINT", self.point_count(), "POINT")
    }

    /// `group:LABELS` (and continuations) cut or extended to `n`, unlabelled entries named
    /// `{stem}{number}`.
    fn labels(&self, group: &str, n: usize, stem: &str) -> Vec<String> {
        let mut l = self.parameters.get_strings_continued(group, "LABELS");
        l.truncate(n);
        while l.len() < n {
            l.push(format!("{stem}{}", l.len() + 1));
        }
        l
    }

    /// Point descriptions (POINT:DESCRIPTIONS, DESCRIPTIONS2, …).
    pub fn point_descriptions(&self) -> Vec<String> {
        let mut d = self
            .parameters
            .get_strings_continued("POINT", "DESCRIPTIONS");
        d.resize(self.point_count(), String::new());
        d
    }

    /// Index of the point labelled `label` (exact match first, then case-insensitive, ignoring
    /// a "Subject:" prefix).
    pub fn point_index(&self, label: &str) -> Option<usize> {
        let labels = self.point_labels();
        labels.iter().position(|l| l == label).or_else(|| {
            let bare = |s: &str| {
                s.rsplit(':')
                    .next()
                    .unwrap_or(s)
                    .trim()
                    .to_ascii_uppercase()
            };
            let want = bare(label);
            labels.iter().position(|l| bare(l) == want)
        })
    }

    /// POINT:UNITS (default "mm").
    pub fn point_units(&self) -> String {
        self.parameters
            .get_strings("POINT", "UNITS")
            .and_then(|v| v.into_iter().next())
            .filter(|s| !s.is_empty())
            .unwrap_or_else(|| "mm".into())
    }

    /// 3D frame rate: POINT:RATE, else the header's.
    pub fn point_rate(&self) -> f32 {
        self.parameters
            .get_f32("POINT", "RATE")
            .filter(|r| *r > 0.0)
            .unwrap_or(self.header.frame_rate)
    }

    /// Analog sample rate: ANALOG:RATE, else the point rate × samples per frame.
    pub fn analog_rate(&self) -> f32 {
        self.parameters
            .get_f32("ANALOG", "RATE")
            .filter(|r| *r > 0.0)
            .unwrap_or(self.point_rate() * self.layout.analog_samples_per_frame as f32)
    }

    /// First frame number (1-based, as stored; long trials use TRIAL:ACTUAL_START_FIELD).
    pub fn first_frame(&self) -> usize {
        let p = self
            .parameters
            .get("TRIAL", "ACTUAL_START_FIELD")
            .map(|p| p.as_u16s());
        match p.as_deref() {
            Some([lo, hi, ..]) if self.header.last_frame == 65535 || self.frames() > 65535 => {
                *lo as usize + ((*hi as usize) << 16)
            }
            _ => self.header.first_frame as usize,
        }
    }

    /// The file's own number of the frame at `index` (0 = the first frame stored):
    /// [`first_frame`](Self::first_frame) + `index`. Every report, export and JSON speaks these
    /// numbers, so a trial cropped to frames 290–700 in the capture software says 290–700
    /// everywhere, as the software that wrote it does.
    pub fn frame_number(&self, index: usize) -> usize {
        self.first_frame() + index
    }

    /// The time in seconds of the frame at `index` on the file's one time base: frame 1 of
    /// the capture is at 0 s, so frame `n` is at (`n` − 1) / POINT:RATE. This is the base of
    /// the EVENT group's TIMES (frame = round(time × rate) + 1 in Vicon's and BTK's
    /// reading), so events, forces and exports line up without an offset. 0 when the file
    /// states no usable rate.
    pub fn frame_time(&self, index: usize) -> f64 {
        let rate = self.point_rate() as f64;
        if rate > 0.0 && rate.is_finite() {
            (self.frame_number(index).saturating_sub(1)) as f64 / rate
        } else {
            0.0
        }
    }

    /// The time in seconds of analog sample `sample` (0 = the first stored) on the same base
    /// as [`frame_time`](Self::frame_time): the first analog sample of a frame is taken at the
    /// frame's time, the others follow at ANALOG:RATE.
    pub fn analog_time(&self, sample: usize) -> f64 {
        let rate = self.analog_rate() as f64;
        let start = self.frame_time(0);
        if rate > 0.0 && rate.is_finite() {
            start + sample as f64 / rate
        } else {
            start
        }
    }

    /// Analog channel labels (ANALOG:LABELS, LABELS2, …), one per channel.
    pub fn analog_labels(&self) -> Vec<String> {
        self.labels("ANALOG", self.analog_channels(), "CHANNEL")
    }

    /// Analog units per channel (ANALOG:UNITS).
    pub fn analog_units(&self) -> Vec<String> {
        let mut u = self.parameters.get_strings_continued("ANALOG", "UNITS");
        u.resize(self.analog_channels(), String::new());
        u
    }

    /// The calibration from ANALOG:SCALE, OFFSET, GEN_SCALE and FORMAT. Missing entries
    /// default to scale 1, offset 0; offsets of unsigned data are read as unsigned.
    pub fn analog_calibration(&self) -> Calibration {
        let ps = &self.parameters;
        let n = self.analog_channels();
        let unsigned = self.layout.unsigned_analog;
        let mut scale = ps
            .get("ANALOG", "SCALE")
            .map(|p| p.as_f32s())
            .unwrap_or_default();
        scale.resize(n, 1.0);
        let mut offset: Vec<f32> = match ps.get("ANALOG", "OFFSET") {
            Some(p) if unsigned => p.as_u16s().into_iter().map(|v| v as f32).collect(),
            Some(p) => p.as_f32s(),
            None => Vec::new(),
        };
        offset.resize(n, 0.0);
        Calibration {
            scale,
            offset,
            gen_scale: ps.get_f32("ANALOG", "GEN_SCALE").unwrap_or(1.0),
            unsigned,
        }
    }

    /// Analog data in physical units, laid out like [`Analog::raw`].
    pub fn analog_physical(&self) -> Vec<f32> {
        self.analog_calibration().apply(self.analog())
    }

    /// The force plates FORCE_PLATFORM describes, checked against the analog channels.
    pub fn platform_params(&self) -> crate::PlatformParams {
        crate::platform_params(&self.parameters, self.analog_channels())
    }

    /// Events from the header and from the EVENT group.
    pub fn header_events(&self) -> Vec<HeaderEvent> {
        self.header.events()
    }

    pub fn events(&self) -> Vec<Event> {
        events::from_parameters(&self.parameters)
    }
}
