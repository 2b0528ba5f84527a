//! Charts drawn with plotters to PNG or SVG, for the command line (behind the `cli` feature): line,
//! scatter and heat-map charts here, the studies' own layouts (mode shapes, Campbell, work–precision,
//! stability maps) in [`charts`]. Text needs a TrueType font: the system's DejaVu Sans (Debian package
//! fonts-dejavu-core) is registered at first use; no font file is shipped in this repository.

use anyhow::{Context, anyhow};
use plotters::prelude::*;
use std::path::Path;

const FONT_PATHS: [&str; 3] = [
    "/usr/share/fonts/truetype/dejavu/DejaVuSans.ttf",
    "/usr/share/fonts/TTF/DejaVuSans.ttf",
    "/usr/share/fonts/dejavu/DejaVuSans.ttf",
];

pub(crate) fn register_font() -> anyhow::Result<()> {
    static DONE: std::sync::OnceLock<Result<(), String>> = std::sync::OnceLock::new();
    DONE.get_or_init(|| {
        let path = std::env::var("WINDRIVE_FONT")
            .ok()
            .or_else(|| FONT_PATHS.iter().find(|p| Path::new(p).is_file()).map(|p| p.to_string()))
            .ok_or("no TrueType font found for plot text: install fonts-dejavu-core or set WINDRIVE_FONT=/path/to/font.ttf")?;
        let bytes: &'static [u8] = std::fs::read(&path).map_err(|e| format!("{path}: {e}"))?.leak();
        plotters::style::register_font("sans-serif", FontStyle::Normal, bytes).map_err(|_| format!("{path}: not a usable font"))
    })
    .clone()
    .map_err(|e| anyhow!(e))
}

/// Runs `$draw(root, args...)` on a PNG or SVG drawing area by the file's extension (the two
/// backends are different types, so a function cannot take either).
macro_rules! on_backend {
    ($path:expr, $draw:ident($($arg:expr),*)) => {{
        register_font()?;
        let path: &Path = $path;
        match path.extension().and_then(|e| e.to_str()).unwrap_or("").to_ascii_lowercase().as_str() {
            "png" => $draw(BitMapBackend::new(path, (1000, 600)).into_drawing_area(), $($arg),*),
            "svg" => $draw(SVGBackend::new(path, (1000, 600)).into_drawing_area(), $($arg),*),
            _ => Err(anyhow!("{}: plot format must be .png or .svg", path.display())),
        }
    }};
}

// after the macro: the charts draw through it
mod charts;
pub use charts::{
    StabilityPanel, campbell, gearbox_modes, mode_shapes, stability_panels, work_precision, write_stability_map,
};

/// Writes `table` to STEM.csv and a chart to STEM.png and STEM.svg by `draw(path)`, and says where.
pub fn write_chart_and_table(
    stem: &Path,
    table: &str,
    draw: impl Fn(&Path) -> anyhow::Result<()>,
) -> anyhow::Result<()> {
    let csv = stem.with_extension("csv");
    std::fs::write(&csv, table).with_context(|| format!("{}: cannot write the table", csv.display()))?;
    for ext in ["png", "svg"] {
        draw(&stem.with_extension(ext))?;
    }
    println!(
        "\nchart: {}  {}  table: {}",
        stem.with_extension("png").display(),
        stem.with_extension("svg").display(),
        csv.display()
    );
    Ok(())
}

/// A line chart of several series, to PNG or SVG by extension.
pub struct Series<'a> {
    pub label: String,
    pub points: &'a [(f64, f64)],
}

pub fn lines(
    path: &Path,
    title: &str,
    x_label: &str,
    y_label: &str,
    series: &[Series],
    markers: &[(f64, String)],
) -> anyhow::Result<()> {
    lines_named(path, title, x_label, y_label, series, markers, None)
}

/// As [`lines`], of (label, points) pairs.
pub fn named_lines(
    path: &Path,
    title: &str,
    x_label: &str,
    y_label: &str,
    lines: &[(String, Vec<(f64, f64)>)],
    markers: &[(f64, String)],
) -> anyhow::Result<()> {
    self::lines(path, title, x_label, y_label, &labelled(lines), markers)
}

/// (label, points) pairs as the series the charts draw.
pub(crate) fn labelled(lines: &[(String, Vec<(f64, f64)>)]) -> Vec<Series<'_>> {
    lines
        .iter()
        .map(|(label, points)| Series {
            label: label.clone(),
            points,
        })
        .collect()
}

/// As [`lines`], with category names for integer x positions.
pub fn lines_named(
    path: &Path,
    title: &str,
    x_label: &str,
    y_label: &str,
    series: &[Series],
    markers: &[(f64, String)],
    x_names: Option<&[String]>,
) -> anyhow::Result<()> {
    on_backend!(path, draw(title, x_label, y_label, series, markers, x_names))
}

fn draw<DB: DrawingBackend>(
    root: DrawingArea<DB, plotters::coord::Shift>,
    title: &str,
    x_label: &str,
    y_label: &str,
    series: &[Series],
    markers: &[(f64, String)],
    x_names: Option<&[String]>,
) -> anyhow::Result<()>
where
    DB::ErrorType: 'static,
{
    let err = |e: DrawingAreaErrorKind<DB::ErrorType>| anyhow!("plot: {e:?}");
    root.fill(&WHITE).map_err(err)?;
    let all = series.iter().flat_map(|s| s.points.iter());
    let (mut x0, mut x1, mut y0, mut y1) = (f64::MAX, f64::MIN, f64::MAX, f64::MIN);
    for &(x, y) in all {
        x0 = x0.min(x);
        x1 = x1.max(x);
        y0 = y0.min(y);
        y1 = y1.max(y);
    }
    if x0 >= x1 {
        x1 = x0 + 1.0;
    }
    let pad = 0.05 * (y1 - y0).abs().max(1e-12);
    let mut chart = ChartBuilder::on(&root)
        .caption(title, ("sans-serif", 22))
        .margin(12)
        .x_label_area_size(45)
        .y_label_area_size(80)
        .build_cartesian_2d(x0..x1, (y0 - pad)..(y1 + pad))
        .map_err(err)?;
    let name_of = |x: &f64| match x_names {
        Some(names) if (x - x.round()).abs() < 1e-9 && x.round() >= 0.0 => {
            names.get(x.round() as usize).cloned().unwrap_or_default()
        }
        Some(_) => String::new(),
        // ticks land on binary fractions (-2.3000000000000003): four decimals, trailing zeros cut
        None => {
            let text = format!("{x:.4}");
            let text = text.trim_end_matches('0').trim_end_matches('.');
            if text == "-0" { "0".into() } else { text.to_string() }
        }
    };
    let mut mesh = chart.configure_mesh();
    mesh.x_desc(x_label).y_desc(y_label).x_label_formatter(&name_of);
    if let Some(names) = x_names {
        mesh.x_labels(names.len());
    }
    mesh.draw().map_err(err)?;
    for (i, s) in series.iter().enumerate() {
        let color = Palette99::pick(i).to_rgba();
        chart
            .draw_series(LineSeries::new(s.points.iter().cloned(), color.stroke_width(2)))
            .map_err(err)?
            .label(s.label.clone())
            .legend(move |(x, y)| PathElement::new(vec![(x, y), (x + 18, y)], color.stroke_width(2)));
    }
    // labels of close markers would overprint: in order along x, each a line below the previous
    let mut order: Vec<usize> = (0..markers.len()).collect();
    order.sort_by(|&i, &j| markers[i].0.total_cmp(&markers[j].0));
    for (rank, &k) in order.iter().enumerate() {
        let (x, label) = &markers[k];
        let y_text = y1 - (rank % 3) as f64 * 0.06 * (y1 - y0 + 2.0 * pad);
        chart
            .draw_series(std::iter::once(PathElement::new(
                vec![(*x, y0 - pad), (*x, y1 + pad)],
                BLACK.mix(0.4),
            )))
            .map_err(err)?;
        chart
            .draw_series(std::iter::once(Text::new(
                label.clone(),
                (*x, y_text),
                ("sans-serif", 14),
            )))
            .map_err(err)?;
    }
    if series.len() > 1 {
        chart
            .configure_series_labels()
            .background_style(WHITE.mix(0.8))
            .border_style(BLACK)
            .draw()
            .map_err(err)?;
    }
    root.present().map_err(err)?;
    Ok(())
}

/// A scatter plot of point clouds, one colour each (e.g. rainflow range against mean).
pub fn scatter(
    path: &Path,
    title: &str,
    x_label: &str,
    y_label: &str,
    clouds: &[(String, Vec<(f64, f64)>)],
) -> anyhow::Result<()> {
    on_backend!(path, draw_scatter(title, x_label, y_label, clouds))
}

fn draw_scatter<DB: DrawingBackend>(
    root: DrawingArea<DB, plotters::coord::Shift>,
    title: &str,
    x_label: &str,
    y_label: &str,
    clouds: &[(String, Vec<(f64, f64)>)],
) -> anyhow::Result<()>
where
    DB::ErrorType: 'static,
{
    let err = |e: DrawingAreaErrorKind<DB::ErrorType>| anyhow!("plot: {e:?}");
    root.fill(&WHITE).map_err(err)?;
    let all = clouds.iter().flat_map(|(_, p)| p.iter());
    let (mut x0, mut x1, mut y0, mut y1) = (f64::MAX, f64::MIN, 0.0f64, f64::MIN);
    for &(x, y) in all {
        (x0, x1, y0, y1) = (x0.min(x), x1.max(x), y0.min(y), y1.max(y));
    }
    if x0 >= x1 {
        (x0, x1) = (x0 - 1.0, x0 + 1.0);
    }
    if y1 <= y0 {
        y1 = y0 + 1.0;
    }
    let mut chart = ChartBuilder::on(&root)
        .caption(title, ("sans-serif", 22))
        .margin(12)
        .x_label_area_size(45)
        .y_label_area_size(80)
        .build_cartesian_2d(x0..x1, y0..y1 * 1.05)
        .map_err(err)?;
    chart
        .configure_mesh()
        .x_desc(x_label)
        .y_desc(y_label)
        .draw()
        .map_err(err)?;
    for (i, (label, pts)) in clouds.iter().enumerate() {
        let color = Palette99::pick(i).to_rgba();
        chart
            .draw_series(pts.iter().map(|&p| Circle::new(p, 3, color.filled())))
            .map_err(err)?
            .label(label.clone())
            .legend(move |(x, y)| Circle::new((x + 9, y), 4, color.filled()));
    }
    chart
        .configure_series_labels()
        .background_style(WHITE.mix(0.8))
        .border_style(BLACK)
        .draw()
        .map_err(err)?;
    root.present().map_err(err)?;
    Ok(())
}

/// A heat map of counts on a grid of cells (x bins × y bins, row-major by y), shaded by log10 of the
/// count (empty cells white): a rainflow matrix.
pub struct Grid<'a> {
    pub x: (f64, f64, usize),
    pub y: (f64, f64, usize),
    /// counts[iy * x.2 + ix]
    pub counts: &'a [f64],
}

pub fn heatmap(path: &Path, title: &str, x_label: &str, y_label: &str, grid: &Grid) -> anyhow::Result<()> {
    on_backend!(path, draw_heatmap(title, x_label, y_label, grid))
}

fn draw_heatmap<DB: DrawingBackend>(
    root: DrawingArea<DB, plotters::coord::Shift>,
    title: &str,
    x_label: &str,
    y_label: &str,
    g: &Grid,
) -> anyhow::Result<()>
where
    DB::ErrorType: 'static,
{
    let err = |e: DrawingAreaErrorKind<DB::ErrorType>| anyhow!("plot: {e:?}");
    root.fill(&WHITE).map_err(err)?;
    let (x0, x1, nx) = g.x;
    let (y0, y1, ny) = g.y;
    let (dx, dy) = ((x1 - x0) / nx as f64, (y1 - y0) / ny as f64);
    let max = g.counts.iter().cloned().fold(0.0f64, f64::max);
    let mut chart = ChartBuilder::on(&root)
        .caption(format!("{title} (shade: log10 count, max {max})"), ("sans-serif", 20))
        .margin(12)
        .x_label_area_size(45)
        .y_label_area_size(80)
        .build_cartesian_2d(x0..x1, y0..y1)
        .map_err(err)?;
    chart
        .configure_mesh()
        .x_desc(x_label)
        .y_desc(y_label)
        .draw()
        .map_err(err)?;
    let top = (max.max(1.0)).log10().max(1e-9);
    let cells = (0..ny)
        .flat_map(|iy| (0..nx).map(move |ix| (ix, iy)))
        .filter_map(|(ix, iy)| {
            let c = g.counts[iy * nx + ix];
            (c > 0.0).then(|| {
                // from pale yellow (one half cycle) to dark red (the largest count)
                let f = ((c.max(0.5) * 2.0).log10() / (top + 2f64.log10())).clamp(0.0, 1.0);
                let color = RGBColor(
                    255 - (f * 100.0) as u8,
                    (230.0 * (1.0 - f)) as u8,
                    (120.0 * (1.0 - f)) as u8,
                );
                let (xa, ya) = (x0 + ix as f64 * dx, y0 + iy as f64 * dy);
                Rectangle::new([(xa, ya), (xa + dx, ya + dy)], color.filled())
            })
        });
    chart.draw_series(cells).map_err(err)?;
    root.present().map_err(err)?;
    Ok(())
}
