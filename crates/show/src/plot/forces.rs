//! `c3dfix plot --forces`: each plate's vertical ground reaction against time, and the
//! centres of pressure over the plates' outlines seen from above.
//!
//! The force drawn is the lab-frame force's component along the lab's vertical axis (the
//! axis the plates' surfaces face, [`c3dfix::axes::platforms_up`]), as `forces` reports
//! it: the reaction on the body, positive while a foot pushes on the plate in a lab whose
//! vertical axis points up. The plate-frame normal force is not drawn,
//! because its sign follows each plate's own axes, which differ between plates of one lab.

use super::decimate;
use super::draw::{font, png_bytes, Format};
use crate::marks::Mark;
use crate::{Error, Result};
use c3dfix::axes::{horizontal_axes, platforms_up};
use c3dfix::ForcePlatforms;
use plotters::coord::Shift;
use plotters::prelude::*;

const W: u32 = 900;
const H: u32 = 1000;
/// Centres of pressure drawn per plate at most: a 10 000-sample stance draws the same path
/// from every few samples.
const MAX_COP_POINTS: usize = 4000;

const PALETTE: [RGBColor; 6] = [
    RGBColor(31, 119, 180),
    RGBColor(214, 39, 40),
    RGBColor(44, 160, 44),
    RGBColor(148, 103, 189),
    RGBColor(255, 127, 14),
    RGBColor(140, 86, 75),
];

fn colour(k: usize) -> RGBColor {
    PALETTE[k % PALETTE.len()]
}

/// Draw the plates of `fp` (from the file `name`) as SVG or PNG bytes.
/// `events` are drawn over the vertical force as on the marker plots.
pub fn render_forces(
    fp: &ForcePlatforms,
    name: &str,
    events: &[Mark],
    format: Format,
) -> Result<Vec<u8>> {
    if fp.platforms.is_empty() {
        return Err(Error::NoPlates {
            file: name.into(),
            warned: !fp.warnings.is_empty(),
        });
    }
    let family = font()?;
    match format {
        Format::Svg => {
            let mut s = String::new();
            {
                let root = SVGBackend::with_string(&mut s, (W, H)).into_drawing_area();
                draw(fp, name, events, family, &root)?;
                root.present().map_err(|e| Error::Draw(e.to_string()))?;
            }
            Ok(s.into_bytes())
        }
        Format::Png => {
            let mut px = vec![255u8; W as usize * H as usize * 3];
            {
                let root = BitMapBackend::with_buffer(&mut px, (W, H)).into_drawing_area();
                draw(fp, name, events, family, &root)?;
                root.present().map_err(|e| Error::Draw(e.to_string()))?;
            }
            png_bytes(&px, W, H)
        }
    }
}

fn draw<DB: DrawingBackend>(
    fp: &ForcePlatforms,
    name: &str,
    events: &[Mark],
    family: &'static str,
    root: &DrawingArea<DB, Shift>,
) -> Result<()> {
    let err = |e: DrawingAreaErrorKind<DB::ErrorType>| Error::Draw(e.to_string());
    root.fill(&WHITE).map_err(err)?;
    let body = root
        .titled(&format!("{name}: force plates"), (family, 22))
        .map_err(err)?;
    let (_, h) = body.dim_in_pixel();
    let (top, bottom) = body.split_vertically(h * 2 / 5);
    let up = platforms_up(fp).map_or(2, |d| d.axis);
    draw_vertical(fp, up, events, family, &top)?;
    draw_top_view(fp, up, family, &bottom)?;
    Ok(())
}

/// The range of `values`, padded; (-1, 1) when none is finite.
fn range(values: impl Iterator<Item = f64>) -> (f64, f64) {
    let (mut lo, mut hi) = (f64::INFINITY, f64::NEG_INFINITY);
    for v in values.filter(|v| v.is_finite()) {
        lo = lo.min(v);
        hi = hi.max(v);
    }
    if !lo.is_finite() {
        return (-1.0, 1.0);
    }
    let pad = ((hi - lo) * 0.05).max(1e-3 * (1.0 + lo.abs().max(hi.abs())));
    (lo - pad, hi + pad)
}

fn draw_vertical<DB: DrawingBackend>(
    fp: &ForcePlatforms,
    up: usize,
    events: &[Mark],
    family: &'static str,
    area: &DrawingArea<DB, Shift>,
) -> Result<()> {
    let err = |e: DrawingAreaErrorKind<DB::ErrorType>| Error::Draw(e.to_string());
    let rate = fp.platforms[0].rate;
    let (dx, xdesc) = if rate > 0.0 {
        (1.0 / rate, "Time (s)")
    } else {
        (1.0, "Sample")
    };
    let n = fp.samples();
    // On the file's time base, as the contacts, events and exports are.
    let x0 = if rate > 0.0 { fp.start_time } else { 0.0 };
    let t1 = x0 + (n.max(2) - 1) as f64 * dx;
    let (lo, hi) = range(
        fp.platforms
            .iter()
            .flat_map(|p| p.force.iter().map(move |f| f[up])),
    );
    let axis = ["X", "Y", "Z"][up];
    let columns = area.dim_in_pixel().0 as usize;
    let mut chart = ChartBuilder::on(area)
        .caption(
            format!("vertical ground reaction (lab {axis})"),
            (family, 15),
        )
        .margin(10)
        .x_label_area_size(36)
        .y_label_area_size(70)
        .build_cartesian_2d(x0..t1, lo..hi)
        .map_err(err)?;
    chart
        .configure_mesh()
        .x_desc(xdesc)
        .y_desc(format!("F{} (N)", axis.to_ascii_lowercase()))
        .label_style((family, 12))
        .axis_desc_style((family, 13))
        .light_line_style(TRANSPARENT)
        .bold_line_style(RGBColor(225, 225, 225))
        .draw()
        .map_err(err)?;
    for (k, p) in fp.platforms.iter().enumerate() {
        let values: Vec<f32> = p.force.iter().map(|f| f[up] as f32).collect();
        let valid = vec![true; values.len()];
        let c = colour(k);
        chart
            .draw_series(
                decimate::polylines(x0, dx, &values, &valid, columns)
                    .into_iter()
                    .map(move |l| PathElement::new(l, c.stroke_width(1))),
            )
            .map_err(err)?
            .label(format!("plate {}", p.index))
            .legend(move |(x, y)| PathElement::new(vec![(x, y), (x + 16, y)], c.stroke_width(2)));
    }
    super::draw::draw_events(&mut chart, events, (x0, t1), (lo, hi), true)?;
    // `family` is the embedded font's (`draw::font`), which the legend uses too.
    super::draw::draw_legend(&mut chart)
}

fn draw_top_view<DB: DrawingBackend>(
    fp: &ForcePlatforms,
    up: usize,
    family: &'static str,
    area: &DrawingArea<DB, Shift>,
) -> Result<()> {
    let err = |e: DrawingAreaErrorKind<DB::ErrorType>| Error::Draw(e.to_string());
    let [a, b] = horizontal_axes(up);
    let names = ["X", "Y", "Z"];
    let units = &fp.platforms[0].units.position;
    let finite = |c: &[f64; 3]| c.iter().all(|x| x.is_finite());
    let shown: Vec<[f64; 3]> = fp
        .platforms
        .iter()
        .flat_map(|p| p.corners.iter().chain(p.cop.iter().filter(|c| finite(c))))
        .copied()
        .collect();
    let (mut x0, mut x1) = range(shown.iter().map(|c| c[a]));
    let (mut y0, mut y1) = range(shown.iter().map(|c| c[b]));
    // Equal scales on both axes, so the plates keep their shape: widen the narrower range to
    // the plotting area's proportions (the area less the label margins).
    let (pw, ph) = area.dim_in_pixel();
    let (pw, ph) = (
        pw.saturating_sub(100).max(1) as f64,
        ph.saturating_sub(90).max(1) as f64,
    );
    let per_px = ((x1 - x0) / pw).max((y1 - y0) / ph);
    let (cx, cy) = ((x0 + x1) / 2.0, (y0 + y1) / 2.0);
    (x0, x1) = (cx - per_px * pw / 2.0, cx + per_px * pw / 2.0);
    (y0, y1) = (cy - per_px * ph / 2.0, cy + per_px * ph / 2.0);

    let mut chart = ChartBuilder::on(area)
        .caption("centre of pressure, seen from above", (family, 15))
        .margin(10)
        .x_label_area_size(36)
        .y_label_area_size(70)
        .build_cartesian_2d(x0..x1, y0..y1)
        .map_err(err)?;
    chart
        .configure_mesh()
        .x_desc(format!("lab {} ({units})", names[a]))
        .y_desc(format!("lab {} ({units})", names[b]))
        .label_style((family, 12))
        .axis_desc_style((family, 13))
        .light_line_style(TRANSPARENT)
        .bold_line_style(RGBColor(235, 235, 235))
        .draw()
        .map_err(err)?;
    for (k, p) in fp.platforms.iter().enumerate() {
        let c = colour(k);
        let outline: Vec<(f64, f64)> = p.corners.iter().map(|v| (v[a], v[b])).collect();
        chart
            .draw_series(std::iter::once(Polygon::new(
                outline.clone(),
                c.mix(0.08).filled(),
            )))
            .map_err(err)?;
        let mut closed = outline;
        closed.push(closed[0]);
        chart
            .draw_series(std::iter::once(PathElement::new(closed, c.stroke_width(2))))
            .map_err(err)?;
        chart
            .draw_series(std::iter::once(Text::new(
                format!("plate {}", p.index),
                (p.centre[a], p.centre[b]),
                (family, 13).into_font().color(&c),
            )))
            .map_err(err)?;
        // The path, broken where the COP is undefined.
        let step = p.cop.len().div_ceil(MAX_COP_POINTS).max(1);
        let mut lines = Vec::new();
        let mut line = Vec::new();
        for v in p.cop.iter().step_by(step) {
            if finite(v) {
                line.push((v[a], v[b]));
            } else if !line.is_empty() {
                lines.push(std::mem::take(&mut line));
            }
        }
        if !line.is_empty() {
            lines.push(line);
        }
        chart
            .draw_series(
                lines
                    .into_iter()
                    .map(move |l| PathElement::new(l, c.stroke_width(2))),
            )
            .map_err(err)?;
    }
    Ok(())
}
