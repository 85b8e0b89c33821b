//! Drawing gathered plots as SVG or PNG with `plotters`.

use super::decimate;
use super::gather::{AnalogPlot, KeyframeCurves, MarkerPlot, Plot, Track, MAX_MARKERS};
use crate::marks::Mark;
use crate::{Error, Result};
use bvh::interp::Interp;
use plotters::coord::types::RangedCoordf64;
use plotters::coord::Shift;
use plotters::prelude::*;
use plotters::style::text_anchor::{HPos, Pos, VPos};

/// The font every label is measured (and, for PNG, drawn) with: embedded so that plotting
/// needs no system font libraries. DejaVu Sans, licence in `crates/show/assets/DejaVuSans-LICENSE.txt`.
static FONT: &[u8] = include_bytes!("../../assets/DejaVuSans.ttf");
const FAMILY: &str = "sans-serif";

const ORIGINAL: RGBColor = RGBColor(31, 119, 180);
const REPAIRED: RGBColor = RGBColor(255, 127, 14);
const FILLED: RGBColor = RGBColor(44, 160, 44);
const SPIKE: RGBColor = RGBColor(214, 39, 40);
const ANALOG: RGBColor = RGBColor(90, 90, 90);
/// The file's own events and detected ones: two colours, so neither passes for the other,
/// and neither is a plate's colour on `plot --forces`.
const EVENT: RGBColor = RGBColor(227, 119, 194);
const DETECTED: RGBColor = RGBColor(128, 128, 0);

const PANEL_W: u32 = 640;
const PANEL_H: u32 = 250;
const TITLE_H: u32 = 44;

/// Output picture format, chosen from the output file's extension.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Format {
    Svg,
    Png,
}

impl Format {
    pub fn from_path(path: &std::path::Path) -> Result<Format> {
        match path
            .extension()
            .and_then(|e| e.to_str())
            .map(|e| e.to_ascii_lowercase())
            .as_deref()
        {
            Some("svg") => Ok(Format::Svg),
            Some("png") => Ok(Format::Png),
            _ => Err(Error::PictureFormat {
                path: path.to_path_buf(),
            }),
        }
    }
}

impl Plot {
    /// Picture size in pixels: one column of panels per marker, rows x, y, z (+ analog).
    pub fn size(&self) -> (u32, u32) {
        let cols = self.markers.len().clamp(1, MAX_MARKERS) as u32;
        let rows = 3 + u32::from(self.analog.is_some());
        (PANEL_W * cols, TITLE_H + PANEL_H * rows)
    }
}

/// Register the embedded font and return its family name: every chart's text must use it,
/// since no system fonts are assumed. Registering twice is harmless.
pub fn font() -> Result<&'static str> {
    plotters::style::register_font(FAMILY, FontStyle::Normal, FONT).map_err(|_| Error::Font)?;
    Ok(FAMILY)
}

/// Draw `plot` as SVG or PNG bytes.
pub fn render(plot: &Plot, format: Format) -> Result<Vec<u8>> {
    font()?;
    let (w, h) = plot.size();
    match format {
        Format::Svg => {
            let mut s = String::new();
            {
                let root = SVGBackend::with_string(&mut s, (w, h)).into_drawing_area();
                draw(plot, &root)?;
                root.present().map_err(|e| Error::Draw(e.to_string()))?;
            }
            Ok(s.into_bytes())
        }
        Format::Png => {
            let mut px = vec![255u8; w as usize * h as usize * 3];
            {
                let root = BitMapBackend::with_buffer(&mut px, (w, h)).into_drawing_area();
                draw(plot, &root)?;
                root.present().map_err(|e| Error::Draw(e.to_string()))?;
            }
            png_bytes(&px, w, h)
        }
    }
}

/// An RGB pixel buffer of `w` × `h` as PNG bytes.
pub(super) fn png_bytes(px: &[u8], w: u32, h: u32) -> Result<Vec<u8>> {
    let mut out = Vec::new();
    let mut enc = png::Encoder::new(&mut out, w, h);
    enc.set_color(png::ColorType::Rgb);
    enc.set_depth(png::BitDepth::Eight);
    let mut wr = enc.write_header()?;
    wr.write_image_data(px)?;
    wr.finish()?;
    Ok(out)
}

/// The range of the valid values in `sets`, padded so lines do not touch the frame.
fn value_range<'a>(sets: impl Iterator<Item = (&'a [f32], &'a [bool])>) -> (f64, f64) {
    let mut lo = f64::INFINITY;
    let mut hi = f64::NEG_INFINITY;
    for (v, ok) in sets {
        for (x, &k) in v.iter().zip(ok) {
            if k && x.is_finite() {
                lo = lo.min(*x as f64);
                hi = hi.max(*x as f64);
            }
        }
    }
    if !lo.is_finite() {
        return (-1.0, 1.0);
    }
    let pad = ((hi - lo) * 0.05).max(1e-3 * (1.0 + lo.abs().max(hi.abs())));
    (lo - pad, hi + pad)
}

fn draw<DB: DrawingBackend>(plot: &Plot, root: &DrawingArea<DB, Shift>) -> Result<()> {
    let err = |e: DrawingAreaErrorKind<DB::ErrorType>| Error::Draw(e.to_string());
    root.fill(&WHITE).map_err(err)?;
    let body = root.titled(&plot.title, (FAMILY, 22)).map_err(err)?;
    let (_, h) = body.dim_in_pixel();
    let (top, bottom) = match plot.analog {
        Some(_) => {
            let (t, b) = body.split_vertically(h * 3 / 4);
            (t, Some(b))
        }
        None => (body, None),
    };
    let shown = plot.markers.iter().take(MAX_MARKERS).collect::<Vec<_>>();
    let panels = top.split_evenly((3, shown.len().max(1)));
    let (dx, xdesc) = if plot.rate > 0.0 {
        (1.0 / plot.rate, "Time (s)")
    } else {
        (1.0, "Frame")
    };
    for (col, m) in shown.iter().enumerate() {
        for axis in 0..3 {
            let area = &panels[axis * shown.len() + col];
            // A legend atop each marker's column: what is marked differs per marker.
            draw_axis(plot, m, axis, dx, xdesc, area, axis == 0)?;
        }
    }
    if let (Some(a), Some(area)) = (&plot.analog, bottom) {
        draw_analog(a, &plot.events, &area)?;
    }
    Ok(())
}

/// One axis of one marker in its panel: the shown trajectory (and the original under a
/// repair), its gaps, the samples filled, filtered and removed as spikes, the events, and
/// the legend when asked.
fn draw_axis<DB: DrawingBackend>(
    plot: &Plot,
    m: &MarkerPlot,
    axis: usize,
    dx: f64,
    xdesc: &str,
    area: &DrawingArea<DB, Shift>,
    legend: bool,
) -> Result<()> {
    let err = |e: DrawingAreaErrorKind<DB::ErrorType>| Error::Draw(e.to_string());
    let name = ["X", "Y", "Z"][axis];
    let comp = |t: &Track| -> Vec<f32> { t.xyz.iter().map(|p| p[axis]).collect() };
    let shown_v = comp(&m.shown);
    let orig_v = m.original.as_ref().map(comp);
    let mut sets: Vec<(&[f32], &[bool])> = vec![(&shown_v, &m.shown.valid)];
    if let (Some(o), Some(ov)) = (&m.original, &orig_v) {
        sets.push((ov, &o.valid));
    }
    let (lo, hi) = value_range(sets.into_iter());
    let n = m
        .shown
        .valid
        .len()
        .max(m.original.as_ref().map_or(0, |o| o.valid.len()));
    let x0 = plot.start;
    let t1 = x0 + (n.max(2) - 1) as f64 * dx;
    let columns = area.dim_in_pixel().0 as usize;

    let mut chart = ChartBuilder::on(area)
        .caption(format!("{} {name}", m.label), (FAMILY, 15))
        .margin(8)
        .x_label_area_size(34)
        .y_label_area_size(64)
        .build_cartesian_2d(x0..t1, lo..hi)
        .map_err(err)?;
    chart
        .configure_mesh()
        .x_desc(xdesc)
        .y_desc(format!("{name} ({})", plot.units))
        .label_style((FAMILY, 12))
        .axis_desc_style((FAMILY, 13))
        .light_line_style(TRANSPARENT)
        .bold_line_style(RGBColor(225, 225, 225))
        .draw()
        .map_err(err)?;

    let at = Across { x0, dx, columns };
    draw_gaps(&mut chart, m, at, (lo, hi))?;
    draw_lines(&mut chart, m, at, &shown_v, orig_v.as_deref())?;
    draw_marks(&mut chart, m, at, n, &shown_v, orig_v.as_deref())?;
    draw_events(&mut chart, &plot.events, (x0, t1), (lo, hi), axis == 0)?;
    if legend {
        draw_legend(&mut chart)?;
    }
    Ok(())
}

/// A panel's chart: time across, values up.
type Chart<'a, DB> = ChartContext<'a, DB, Cartesian2d<RangedCoordf64, RangedCoordf64>>;

/// Where a panel's samples go across it: the first sample's time, the time between samples,
/// and the panel's width in pixels (lines and marks are thinned to what it shows).
#[derive(Clone, Copy)]
struct Across {
    x0: f64,
    dx: f64,
    columns: usize,
}

/// The marker's gaps as shaded spans over the panel's height (`lo..hi`).
fn draw_gaps<DB: DrawingBackend>(
    chart: &mut Chart<'_, DB>,
    m: &MarkerPlot,
    at: Across,
    (lo, hi): (f64, f64),
) -> Result<()> {
    let err = |e: DrawingAreaErrorKind<DB::ErrorType>| Error::Draw(e.to_string());
    let Across { x0, dx, columns } = at;
    let shade = RGBColor(0, 0, 0).mix(0.10).filled();
    let gap_label = if m.original.is_some() {
        "gap in original"
    } else {
        "gap"
    };
    let spans = decimate::spans(&m.gaps, columns);
    if !spans.is_empty() {
        chart
            .draw_series(spans.iter().map(|&(a, b)| {
                Rectangle::new(
                    [
                        (x0 + a as f64 * dx - dx / 2.0, lo),
                        (x0 + b as f64 * dx + dx / 2.0, hi),
                    ],
                    shade,
                )
            }))
            .map_err(err)?
            .label(gap_label)
            .legend(move |(x, y)| Rectangle::new([(x, y - 5), (x + 16, y + 5)], shade));
    }
    Ok(())
}

/// The shown trajectory's line and, under a repair, the original's.
fn draw_lines<DB: DrawingBackend>(
    chart: &mut Chart<'_, DB>,
    m: &MarkerPlot,
    at: Across,
    shown_v: &[f32],
    orig_v: Option<&[f32]>,
) -> Result<()> {
    let err = |e: DrawingAreaErrorKind<DB::ErrorType>| Error::Draw(e.to_string());
    let Across { x0, dx, columns } = at;
    let line = |v: &[f32], ok: &[bool]| decimate::polylines(x0, dx, v, ok, columns);
    // The repaired line goes under the original, wider, so both show where they agree.
    let (colour, label, width) = if m.original.is_some() {
        (REPAIRED, "repaired", 2)
    } else {
        (ORIGINAL, "data", 1)
    };
    chart
        .draw_series(
            line(shown_v, &m.shown.valid)
                .into_iter()
                .map(move |p| PathElement::new(p, colour.stroke_width(width))),
        )
        .map_err(err)?
        .label(label)
        .legend(move |(x, y)| PathElement::new(vec![(x, y), (x + 16, y)], colour.stroke_width(2)));
    if let (Some(o), Some(ov)) = (&m.original, orig_v) {
        chart
            .draw_series(
                line(ov, &o.valid)
                    .into_iter()
                    .map(|p| PathElement::new(p, ORIGINAL.stroke_width(1))),
            )
            .map_err(err)?
            .label("original")
            .legend(|(x, y)| PathElement::new(vec![(x, y), (x + 16, y)], ORIGINAL.stroke_width(2)));
    }
    Ok(())
}

/// The samples filled and filtered on the shown line, and those removed as spikes on the
/// original's, thinned to what the panel's `n` samples across its width can show.
fn draw_marks<DB: DrawingBackend>(
    chart: &mut Chart<'_, DB>,
    m: &MarkerPlot,
    at: Across,
    n: usize,
    shown_v: &[f32],
    orig_v: Option<&[f32]>,
) -> Result<()> {
    let err = |e: DrawingAreaErrorKind<DB::ErrorType>| Error::Draw(e.to_string());
    let Across { x0, dx, columns } = at;
    let filled = decimate::thin(&m.filled, n, columns / 3);
    if !filled.is_empty() {
        chart
            .draw_series(
                filled.iter().map(|&f| {
                    Circle::new((x0 + f as f64 * dx, shown_v[f] as f64), 2, FILLED.filled())
                }),
            )
            .map_err(err)?
            .label("filled (residual 0)")
            .legend(|(x, y)| Circle::new((x + 8, y), 3, FILLED.filled()));
    }
    let filtered = decimate::thin(&m.filtered, n, columns / 3);
    if !filtered.is_empty() {
        chart
            .draw_series(filtered.iter().map(|&f| {
                Circle::new(
                    (x0 + f as f64 * dx, shown_v[f] as f64),
                    1,
                    ORIGINAL.filled(),
                )
            }))
            .map_err(err)?
            .label("filtered")
            .legend(|(x, y)| Circle::new((x + 8, y), 2, ORIGINAL.filled()));
    }
    if let Some(ov) = orig_v {
        let spikes = decimate::thin(&m.spikes, n, columns / 3);
        if !spikes.is_empty() {
            chart
                .draw_series(spikes.iter().map(|&f| {
                    Cross::new((x0 + f as f64 * dx, ov[f] as f64), 4, SPIKE.stroke_width(2))
                }))
                .map_err(err)?
                .label("removed as spike")
                .legend(|(x, y)| Cross::new((x + 8, y), 4, SPIKE.stroke_width(2)));
        }
    }
    Ok(())
}

fn draw_analog<DB: DrawingBackend>(
    a: &AnalogPlot,
    events: &[Mark],
    area: &DrawingArea<DB, Shift>,
) -> Result<()> {
    let err = |e: DrawingAreaErrorKind<DB::ErrorType>| Error::Draw(e.to_string());
    let ok = vec![true; a.values.len()];
    let (lo, hi) = value_range([(a.values.as_slice(), ok.as_slice())].into_iter());
    let (dx, xdesc) = if a.rate > 0.0 {
        (1.0 / a.rate, "Time (s)")
    } else {
        (1.0, "Sample")
    };
    let x0 = a.start;
    let t1 = x0 + (a.values.len().max(2) - 1) as f64 * dx;
    let columns = area.dim_in_pixel().0 as usize;
    let units = if a.units.is_empty() {
        a.label.clone()
    } else {
        format!("{} ({})", a.label, a.units)
    };
    let mut chart = ChartBuilder::on(area)
        .caption(format!("analog {}", a.label), (FAMILY, 15))
        .margin(8)
        .x_label_area_size(34)
        .y_label_area_size(64)
        .build_cartesian_2d(x0..t1, lo..hi)
        .map_err(err)?;
    chart
        .configure_mesh()
        .x_desc(xdesc)
        .y_desc(units)
        .label_style((FAMILY, 12))
        .axis_desc_style((FAMILY, 13))
        .light_line_style(TRANSPARENT)
        .bold_line_style(RGBColor(225, 225, 225))
        .draw()
        .map_err(err)?;
    chart
        .draw_series(
            decimate::polylines(x0, dx, &a.values, &ok, columns)
                .into_iter()
                .map(|p| PathElement::new(p, ANALOG.stroke_width(1))),
        )
        .map_err(err)?;
    draw_events(&mut chart, events, (x0, t1), (lo, hi), false)
}

/// Each event within the x range as a vertical line over the panel's height; with
/// `labels`, its short label at the top (the file's) or the bottom (detected ones, so the
/// two never cover each other), centred on the line, and a legend entry per kind.
/// The series' legend, in the chart's upper right corner, as every chart draws it.
pub(super) fn draw_legend<'a, DB: DrawingBackend + 'a>(
    chart: &mut ChartContext<'a, DB, Cartesian2d<RangedCoordf64, RangedCoordf64>>,
) -> Result<()> {
    let err = |e: DrawingAreaErrorKind<DB::ErrorType>| Error::Draw(e.to_string());
    chart
        .configure_series_labels()
        .label_font((FAMILY, 12))
        .background_style(WHITE.mix(0.85))
        .border_style(RGBColor(180, 180, 180))
        .position(SeriesLabelPosition::UpperRight)
        .draw()
        .map_err(err)
}

pub(super) fn draw_events<DB: DrawingBackend>(
    chart: &mut ChartContext<'_, DB, Cartesian2d<RangedCoordf64, RangedCoordf64>>,
    events: &[Mark],
    (x0, x1): (f64, f64),
    (lo, hi): (f64, f64),
    labels: bool,
) -> Result<()> {
    let err = |e: DrawingAreaErrorKind<DB::ErrorType>| Error::Draw(e.to_string());
    for (detected, colour, name) in [
        (false, EVENT, "events (file)"),
        (true, DETECTED, "events (detected)"),
    ] {
        let shown: Vec<&Mark> = events
            .iter()
            .filter(|e| e.detected == detected && e.time >= x0 && e.time <= x1)
            .collect();
        if shown.is_empty() {
            continue;
        }
        let anno = chart
            .draw_series(shown.iter().map(|e| {
                PathElement::new(vec![(e.time, lo), (e.time, hi)], colour.stroke_width(1))
            }))
            .map_err(err)?;
        if labels {
            anno.label(name).legend(move |(x, y)| {
                PathElement::new(vec![(x + 8, y - 6), (x + 8, y + 6)], colour.stroke_width(2))
            });
            let (y, v) = if detected {
                (lo, VPos::Bottom)
            } else {
                (hi, VPos::Top)
            };
            let style = TextStyle::from((FAMILY, 11).into_font())
                .color(&colour)
                .pos(Pos::new(HPos::Center, v));
            chart
                .draw_series(
                    shown
                        .iter()
                        .map(|e| Text::new(e.short.clone(), (e.time, y), style.clone())),
                )
                .map_err(err)?;
        }
    }
    Ok(())
}

/// Draw the greedy keyframe error curves side by side, one panel per interpolation, as SVG.
pub fn render_keyframe_curves(k: &KeyframeCurves) -> Result<String> {
    // A NaN or infinite error (from values keyframes refuses anyway) would send the axis
    // labelling into an endless loop.
    if k.curves
        .iter()
        .any(|(_, c)| c.iter().any(|p| !p.1.is_finite()))
    {
        return Err(Error::CurveNotFinite);
    }
    let family = font()?;
    let y_max = k
        .curves
        .iter()
        .flat_map(|(_, c)| c.iter().map(|p| p.1))
        .fold(0.0, f64::max)
        .max(1e-9);
    let err = |e: DrawingAreaErrorKind<std::io::Error>| Error::Draw(e.to_string());
    let mut svg = String::new();
    {
        let root = SVGBackend::with_string(&mut svg, (1000, 450)).into_drawing_area();
        root.fill(&WHITE).map_err(err)?;
        let root = root
            .titled(
                &format!("{}: greedy keyframe reduction", k.name),
                (family, 18),
            )
            .map_err(err)?;
        let panels = root.split_evenly((1, 2));
        for ((mode, curve), panel) in k.curves.iter().zip(panels.iter()) {
            let mut chart = ChartBuilder::on(panel)
                .caption(format!("{} interpolation", mode.name()), (family, 16))
                .margin(10)
                .x_label_area_size(40)
                .y_label_area_size(70)
                .build_cartesian_2d(0..k.frames.max(1), 0.0..y_max * 1.05)
                .map_err(err)?;
            chart
                .configure_mesh()
                .x_desc("removed frames")
                .y_desc("total error (squared distance)")
                .draw()
                .map_err(err)?;
            let colour = match mode {
                Interp::Euler => RED,
                Interp::Quat => BLUE,
            };
            chart
                .draw_series(LineSeries::new(curve.iter().copied(), &colour))
                .map_err(err)?;
        }
        root.present().map_err(err)?;
    }
    Ok(svg)
}
