//! [`C3d`]: a whole file as a model — header, parameters, point and analog data — plus the
//! bytes it was read from, so that writing it back changes only what was changed.

use crate::analog::{Analog, Calibration};
use crate::data::Layout;
use crate::error::Warning;
use crate::events::{self, Event};
use crate::header::{Header, HeaderEvent};
use crate::parameters::Parameters;
use crate::points::Points;
use crate::processor::Processor;
use serde::Serialize;

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
    pub bytes: Vec<u8>,
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
#[derive(Debug, Clone)]
pub struct C3d {
    pub header: Header,
    pub parameters: Parameters,
    points: Points,
    analog: Analog,
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
        points: Points,
        analog: Analog,
        layout: Layout,
        processor: Processor,
        warnings: Vec<Warning>,
        source: Source,
    ) -> C3d {
        C3d {
            header,
            parameters,
            points,
            analog,
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
            points,
            analog,
            layout,
            processor,
            warnings: Vec::new(),
            source: None,
            points_dirty: true,
            analog_dirty: true,
        }
    }

    pub fn points(&self) -> &Points {
        &self.points
    }

    /// Mutable point data; samples changed through it are re-encoded when writing.
    pub fn points_mut(&mut self) -> &mut Points {
        self.points_dirty = true;
        &mut self.points
    }

    pub fn analog(&self) -> &Analog {
        &self.analog
    }

    /// Mutable analog data (raw values); changed samples are re-encoded when writing.
    pub fn analog_mut(&mut self) -> &mut Analog {
        self.analog_dirty = true;
        &mut self.analog
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

    /// What in the file broke the rules but could be read around.
    pub fn warnings(&self) -> &[Warning] {
        &self.warnings
    }

    /// The bytes the file was read from, if it was read.
    pub fn source_bytes(&self) -> Option<&[u8]> {
        self.source.as_ref().map(|s| s.bytes.as_slice())
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
        self.labels("POINT", self.points.count, "POINT")
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
        d.resize(self.points.count, String::new());
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
            Some([lo, hi, ..]) if self.header.last_frame == 65535 || self.points.frames > 65535 => {
                *lo as usize + ((*hi as usize) << 16)
            }
            _ => self.header.first_frame as usize,
        }
    }

    /// Analog channel labels (ANALOG:LABELS, LABELS2, …), one per channel.
    pub fn analog_labels(&self) -> Vec<String> {
        self.labels("ANALOG", self.analog.channels, "CHANNEL")
    }

    /// Analog units per channel (ANALOG:UNITS).
    pub fn analog_units(&self) -> Vec<String> {
        let mut u = self.parameters.get_strings_continued("ANALOG", "UNITS");
        u.resize(self.analog.channels, String::new());
        u
    }

    /// The calibration from ANALOG:SCALE, OFFSET, GEN_SCALE and FORMAT. Missing entries
    /// default to scale 1, offset 0; offsets of unsigned data are read as unsigned.
    pub fn analog_calibration(&self) -> Calibration {
        let ps = &self.parameters;
        let n = self.analog.channels;
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
        self.analog_calibration().apply(&self.analog)
    }

    /// Events from the header and from the EVENT group.
    pub fn header_events(&self) -> Vec<HeaderEvent> {
        self.header.events()
    }

    pub fn events(&self) -> Vec<Event> {
        events::from_parameters(&self.parameters)
    }
}
