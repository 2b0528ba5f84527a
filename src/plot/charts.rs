//! The charts particular to the studies: mode shapes, the Campbell diagram, the work–precision chart
//! and the stability map. Each lays out its data its own way (log axes, staircases, panels); the
//! generic line, scatter and heat-map charts are in the parent module.

use super::{Series, lines_named, register_font};
use crate::linear::gearbox_modes::{Family, GearMode};
use crate::linear::modes::Modes;
use anyhow::{Context, anyhow};
use plotters::prelude::*;
use plotters::style::text_anchor::{HPos, Pos, VPos};
use std::path::Path;

/// Mode shapes: amplitude per DOF, one line per mode (the first eight).
pub fn mode_shapes(path: &Path, title: &str, m: &Modes) -> anyhow::Result<()> {
    let pts: Vec<(String, Vec<(f64, f64)>)> = m
        .frequencies_hz
        .iter()
        .zip(&m.shapes)
        .take(8)
        .map(|(f, s)| {
            (
                format!("{f:.3} Hz"),
                s.iter().enumerate().map(|(i, v)| (i as f64, *v)).collect(),
            )
        })
        .collect();
    let series: Vec<Series> = pts
        .iter()
        .map(|(l, p)| Series {
            label: l.clone(),
            points: p,
        })
        .collect();
    lines_named(
        path,
        title,
        "degree of freedom",
        "amplitude, referred to the LSS",
        &series,
        &[],
        Some(&m.dof_names),
    )
    .context("mode-shape plot")
}

/// A gearbox's modes: frequency (log10) against torsional share of kinetic energy, a cloud per family,
/// the rigid modes left out.
pub fn gearbox_modes(path: &Path, gearbox: &str, m: &[GearMode]) -> anyhow::Result<()> {
    let mut clouds: Vec<(String, Vec<(f64, f64)>)> = Vec::new();
    for mode in m.iter().filter(|x| x.frequency_hz > 0.0 && x.family != Family::Rigid) {
        let label = mode.family.name().to_string();
        let point = (mode.torsional_projection, mode.frequency_hz.log10());
        match clouds.iter_mut().find(|(l, _)| *l == label) {
            Some((_, pts)) => pts.push(point),
            None => clouds.push((label, vec![point])),
        }
    }
    super::scatter(
        path,
        &format!("{gearbox}: natural frequencies"),
        "torsional share of kinetic energy",
        "log10(f / Hz)",
        &clouds,
    )
}

/// Campbell diagram: natural frequencies (horizontal), excitation orders (rays from the origin),
/// the operating speed range (vertical lines) and the crossings inside it (circles).
pub fn campbell(
    path: &Path,
    title: &str,
    modes_hz: &[f64],
    orders: &[(String, f64)],
    range_rpm: (f64, f64),
    crossings: &[(f64, f64)],
    f_max: f64,
) -> anyhow::Result<()> {
    on_backend!(
        path,
        draw_campbell(title, modes_hz, orders, range_rpm, crossings, f_max)
    )
}

fn draw_campbell<DB: DrawingBackend>(
    root: DrawingArea<DB, plotters::coord::Shift>,
    title: &str,
    modes_hz: &[f64],
    orders: &[(String, f64)],
    (lo, hi): (f64, f64),
    crossings: &[(f64, f64)],
    f_max: f64,
) -> anyhow::Result<()>
where
    DB::ErrorType: 'static,
{
    let err = |e: DrawingAreaErrorKind<DB::ErrorType>| anyhow!("plot: {e:?}");
    root.fill(&WHITE).map_err(err)?;
    let x_max = hi * 1.25;
    // logarithmic frequency: the first drivetrain modes (≈1 Hz, met by 1P/3P) and the mesh
    // frequencies (10²–10³ Hz) in one picture
    let lowest_ray = orders.iter().map(|o| o.1).fold(f64::INFINITY, f64::min) * lo / 60.0;
    let f_min = 0.5
        * modes_hz
            .first()
            .copied()
            .unwrap_or(f_max)
            .min(lowest_ray)
            .min(f_max / 10.0);
    let mut chart = ChartBuilder::on(&root)
        .caption(title, ("sans-serif", 20))
        .margin(12)
        .x_label_area_size(45)
        .y_label_area_size(80)
        .right_y_label_area_size(70)
        .build_cartesian_2d(0.0..x_max, (f_min..f_max).log_scale())
        .map_err(err)?;
    chart
        .configure_mesh()
        .x_desc("rotor speed [rpm]")
        .y_desc("frequency [Hz]")
        .y_label_formatter(&|f| format!("{f}"))
        .draw()
        .map_err(err)?;
    let grey = RGBColor(90, 90, 160);
    let mut last_label = 0.0;
    for (i, &f) in modes_hz.iter().enumerate() {
        let line = chart
            .draw_series(std::iter::once(PathElement::new(
                vec![(0.0, f), (x_max, f)],
                grey.mix(0.6),
            )))
            .map_err(err)?;
        if i == 0 {
            line.label("natural frequency")
                .legend(move |(x, y)| PathElement::new(vec![(x, y), (x + 18, y)], grey));
        }
        // the value at the right edge, where lines are far enough apart to read
        if f / last_label > 1.08 {
            chart
                .draw_series(std::iter::once(Text::new(
                    format!("{f:.3} Hz"),
                    (x_max * 0.995, f),
                    ("sans-serif", 11)
                        .into_font()
                        .color(&grey)
                        .pos(Pos::new(HPos::Right, VPos::Bottom)),
                )))
                .map_err(err)?;
            last_label = f;
        }
    }
    for x in [lo, hi] {
        let edge = chart
            .draw_series(std::iter::once(PathElement::new(
                vec![(x, f_min), (x, f_max)],
                RED.stroke_width(2),
            )))
            .map_err(err)?;
        if x == lo {
            edge.label(format!("operating range {lo}–{hi} rpm"))
                .legend(|(x, y)| PathElement::new(vec![(x, y), (x + 18, y)], RED.stroke_width(2)));
        }
    }
    for (i, (name, order)) in orders.iter().enumerate() {
        let color = Palette99::pick(i + 1).to_rgba();
        // the ray f = order · n/60, sampled so it bends correctly on the log axis, from f_min to the top
        let (x_start, x_end) = (f_min * 60.0 / order, (f_max * 60.0 / order).min(x_max));
        let ray: Vec<(f64, f64)> = (0..=48)
            .map(|k| x_start * (x_end / x_start).powf(k as f64 / 48.0))
            .map(|x| (x, order * x / 60.0))
            .collect();
        chart
            .draw_series(std::iter::once(PathElement::new(ray, color.stroke_width(2))))
            .map_err(err)?
            .label(format!("{name} ({order:.1}×)"))
            .legend(move |(x, y)| PathElement::new(vec![(x, y), (x + 18, y)], color.stroke_width(2)));
    }
    chart
        .draw_series(crossings.iter().map(|&p| Circle::new(p, 7, BLACK.stroke_width(2))))
        .map_err(err)?;
    chart
        .configure_series_labels()
        .position(SeriesLabelPosition::UpperLeft)
        .background_style(WHITE.mix(0.8))
        .border_style(BLACK)
        .draw()
        .map_err(err)?;
    root.present().map_err(err)?;
    Ok(())
}

/// A work–precision chart on log–log axes: one line with markers per method (points in grid order),
/// the Pareto front as a black dashed staircase, and the scene's tightest tolerance as a horizontal
/// dashed line. Points are (CPU time s, relative error), both > 0.
pub fn work_precision(
    path: &Path,
    title: &str,
    lines: &[(String, Vec<(f64, f64)>)],
    front: &[(f64, f64)],
    tolerance: Option<f64>,
) -> anyhow::Result<()> {
    on_backend!(
        path,
        draw_work_precision(title, &super::labelled(lines), front, tolerance)
    )
}

fn draw_work_precision<DB: DrawingBackend>(
    root: DrawingArea<DB, plotters::coord::Shift>,
    title: &str,
    series: &[Series],
    front: &[(f64, f64)],
    tolerance: Option<f64>,
) -> anyhow::Result<()>
where
    DB::ErrorType: 'static,
{
    let err = |e: DrawingAreaErrorKind<DB::ErrorType>| anyhow!("plot: {e:?}");
    root.fill(&WHITE).map_err(err)?;
    let (mut x0, mut x1, mut y0, mut y1) = (f64::MAX, f64::MIN, f64::MAX, f64::MIN);
    for &(x, y) in series
        .iter()
        .flat_map(|s| s.points.iter())
        .chain(tolerance.map(|t| (f64::NAN, t)).iter())
    {
        if x.is_finite() {
            (x0, x1) = (x0.min(x), x1.max(x));
        }
        (y0, y1) = (y0.min(y), y1.max(y));
    }
    if x0.partial_cmp(&x1) != Some(std::cmp::Ordering::Less) {
        (x0, x1) = (x0.min(1.0) / 2.0, x0.max(1e-3) * 2.0);
    }
    if y0.partial_cmp(&y1) != Some(std::cmp::Ordering::Less) {
        (y0, y1) = (y0.min(1.0) / 10.0, y0.max(1e-12) * 10.0);
    }
    let mut chart = ChartBuilder::on(&root)
        .caption(title, ("sans-serif", 20))
        .margin(12)
        .x_label_area_size(45)
        .y_label_area_size(80)
        .build_cartesian_2d((x0 / 1.3..x1 * 1.3).log_scale(), (y0 / 3.0..y1 * 3.0).log_scale())
        .map_err(err)?;
    chart
        .configure_mesh()
        .x_desc("CPU time per run [s]")
        .y_desc("largest relative error of the quantities of interest")
        .y_label_formatter(&|y| format!("{y:.0e}"))
        .x_label_formatter(&|x| {
            let text = format!("{x:.4}");
            text.trim_end_matches('0').trim_end_matches('.').to_string()
        })
        .draw()
        .map_err(err)?;
    if let Some(t) = tolerance {
        let dashes = DashedLineSeries::new(vec![(x0 / 1.3, t), (x1 * 1.3, t)], 8, 6, BLACK.mix(0.5).stroke_width(1));
        chart
            .draw_series(dashes)
            .map_err(err)?
            .label(format!("tightest tolerance {:.0} %", t * 100.0))
            .legend(|(x, y)| PathElement::new(vec![(x, y), (x + 18, y)], BLACK.mix(0.5)));
    }
    for (i, s) in series.iter().enumerate() {
        let color = Palette99::pick(i).to_rgba();
        chart
            .draw_series(LineSeries::new(s.points.iter().cloned(), color.stroke_width(2)))
            .map_err(err)?
            .label(s.label.clone())
            .legend(move |(x, y)| PathElement::new(vec![(x, y), (x + 18, y)], color.stroke_width(2)));
        chart
            .draw_series(s.points.iter().map(|&p| Circle::new(p, 4, color.filled())))
            .map_err(err)?;
    }
    if !front.is_empty() {
        // the staircase: from each front point right to the next one's CPU time, then down
        let mut stair = Vec::new();
        for (k, &(x, y)) in front.iter().enumerate() {
            stair.push((x, y));
            if let Some(&(xn, _)) = front.get(k + 1) {
                stair.push((xn, y));
            }
        }
        chart
            .draw_series(DashedLineSeries::new(stair, 6, 4, BLACK.stroke_width(2)))
            .map_err(err)?
            .label("Pareto front")
            .legend(|(x, y)| PathElement::new(vec![(x, y), (x + 18, y)], BLACK.stroke_width(2)));
        chart
            .draw_series(front.iter().map(|&p| Circle::new(p, 8, BLACK.stroke_width(2))))
            .map_err(err)?;
    }
    chart
        .configure_series_labels()
        .position(SeriesLabelPosition::UpperRight)
        .background_style(WHITE.mix(0.85))
        .border_style(BLACK)
        .draw()
        .map_err(err)?;
    root.present().map_err(err)?;
    Ok(())
}

/// One panel of a stability map: runs that held (green) and grew (red) on (x, y), and a boundary line.
pub struct StabilityPanel {
    pub title: String,
    pub stable: Vec<(f64, f64)>,
    pub unstable: Vec<(f64, f64)>,
    pub boundary: Vec<(f64, f64)>,
}

/// Writes a stability map's table (STEM.csv) and chart (STEM.png, STEM.svg) and says where.
pub fn write_stability_map(
    stem: &Path,
    csv: &str,
    title: &str,
    (x_label, y_label): (&str, &str),
    panels: &[StabilityPanel],
) -> anyhow::Result<()> {
    super::write_chart_and_table(stem, csv, |path| {
        stability_panels(path, title, x_label, y_label, panels)
    })
}

/// Stability maps side by side (two rows), log–log axes shared by every panel.
pub fn stability_panels(
    path: &Path,
    title: &str,
    x_label: &str,
    y_label: &str,
    panels: &[StabilityPanel],
) -> anyhow::Result<()> {
    register_font()?;
    let size = (1400, 760);
    match path
        .extension()
        .and_then(|e| e.to_str())
        .unwrap_or("")
        .to_ascii_lowercase()
        .as_str()
    {
        "png" => draw_stability(
            BitMapBackend::new(path, size).into_drawing_area(),
            title,
            x_label,
            y_label,
            panels,
        ),
        "svg" => draw_stability(
            SVGBackend::new(path, size).into_drawing_area(),
            title,
            x_label,
            y_label,
            panels,
        ),
        _ => Err(anyhow!("{}: plot format must be .png or .svg", path.display())),
    }
}

fn draw_stability<DB: DrawingBackend>(
    root: DrawingArea<DB, plotters::coord::Shift>,
    title: &str,
    x_label: &str,
    y_label: &str,
    panels: &[StabilityPanel],
) -> anyhow::Result<()>
where
    DB::ErrorType: 'static,
{
    let err = |e: DrawingAreaErrorKind<DB::ErrorType>| anyhow!("plot: {e:?}");
    root.fill(&WHITE).map_err(err)?;
    let root = root.titled(title, ("sans-serif", 20)).map_err(err)?;
    let points = || panels.iter().flat_map(|p| p.stable.iter().chain(&p.unstable));
    let (mut x0, mut x1, mut y0, mut y1) = (f64::MAX, f64::MIN, f64::MAX, f64::MIN);
    for &(x, y) in points() {
        (x0, x1, y0, y1) = (x0.min(x), x1.max(x), y0.min(y), y1.max(y));
    }
    if x0 >= x1 || y0 >= y1 {
        return Err(anyhow!("plot: no runs to draw"));
    }
    let columns = panels.len().div_ceil(2).max(1);
    let areas = root.split_evenly((2, columns));
    for (panel, area) in panels.iter().zip(areas.iter()) {
        let mut chart = ChartBuilder::on(area)
            .caption(&panel.title, ("sans-serif", 16))
            .margin(6)
            .x_label_area_size(34)
            .y_label_area_size(44)
            .build_cartesian_2d((x0 / 1.5..x1 * 1.5).log_scale(), (y0 / 1.5..y1 * 1.5).log_scale())
            .map_err(err)?;
        chart
            .configure_mesh()
            .x_desc(x_label)
            .y_desc(y_label)
            .x_labels(4)
            .y_labels(4)
            .x_label_formatter(&|x| format!("{x:.0e}"))
            .y_label_formatter(&|y| format!("{y}"))
            .light_line_style(WHITE)
            .draw()
            .map_err(err)?;
        let green = RGBColor(30, 150, 60);
        chart
            .draw_series(panel.stable.iter().map(|&p| Circle::new(p, 5, green.filled())))
            .map_err(err)?;
        chart
            .draw_series(panel.unstable.iter().map(|&p| Cross::new(p, 5, RED.stroke_width(2))))
            .map_err(err)?;
        if !panel.boundary.is_empty() {
            chart
                .draw_series(LineSeries::new(panel.boundary.iter().cloned(), BLACK.stroke_width(2)))
                .map_err(err)?;
        }
    }
    root.present().map_err(err)?;
    Ok(())
}
