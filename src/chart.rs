//! Speed-versus-accuracy line charts as standalone SVG: linear or log10 axes with ticks and a
//! light grid, one polyline with circle markers per series, a legend to the right of the plot,
//! a title and axis labels.
//!
//! Hand-written rather than taken from a plotting crate: a chart is a few dozen lines of SVG,
//! while a crate would pull font rasterisers and image codecs into every build of the lab.

const WIDTH: f64 = 1000.0;
const HEIGHT: f64 = 560.0;
/// The plot rectangle; the right margin holds the legend so it never covers data or labels.
const LEFT: f64 = 100.0;
const RIGHT: f64 = 690.0;
const TOP: f64 = 50.0;
const BOTTOM: f64 = 490.0;
/// Okabe-Ito (colour-blind friendly), reordered so that the faint yellow comes last.
/// Shared with the recording, so a method has one colour in the chart and in the viewer.
pub const PALETTE: [[u8; 3]; 8] = [
    [0x00, 0x72, 0xB2],
    [0xD5, 0x5E, 0x00],
    [0x00, 0x9E, 0x73],
    [0xCC, 0x79, 0xA7],
    [0xE6, 0x9F, 0x00],
    [0x56, 0xB4, 0xE9],
    [0x00, 0x00, 0x00],
    [0xF0, 0xE4, 0x42],
];
/// Longer legend labels are cut so that the legend stays inside the image.
const LEGEND_CHARS: usize = 36;
const MIDDLE: &str = r#"text-anchor="middle""#;

/// One line of the chart: a label and its points (x, y), drawn in the given order.
pub struct Series {
    /// Legend text (cut to fit the legend).
    pub label: String,
    /// Points (x, y) in data units; one that is not finite, or not positive on a log axis, is
    /// skipped.
    pub points: Vec<(f64, f64)>,
}

/// A line chart of [`Series`], rendered by [`Chart::to_svg`].
pub struct Chart {
    /// Title above the plot.
    pub title: String,
    /// Label under the x axis.
    pub x_label: String,
    /// Label beside the y axis.
    pub y_label: String,
    /// log10 axis when true
    pub x_log: bool,
    /// log10 y axis when true
    pub y_log: bool,
    /// The lines, in drawing order; line i takes colour `PALETTE[i % 8]`.
    pub series: Vec<Series>,
}

impl Chart {
    /// The chart as an SVG document (width 1000, height 560 px).
    pub fn to_svg(&self) -> String {
        // Axes fit only the points that get drawn: a skipped point must not stretch the other axis.
        let drawable = |&&(x, y): &&(f64, f64)| {
            plot_space(x, self.x_log).is_some() && plot_space(y, self.y_log).is_some()
        };
        let points = || self.series.iter().flat_map(|s| &s.points).filter(drawable);
        let x_axis = Axis::fit(points().map(|p| p.0), self.x_log);
        let y_axis = Axis::fit(points().map(|p| p.1), self.y_log);
        let x_pixel = |fraction: f64| LEFT + fraction * (RIGHT - LEFT);
        let y_pixel = |fraction: f64| BOTTOM - fraction * (BOTTOM - TOP);

        let mut svg = Svg(format!(
            "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"{WIDTH}\" height=\"{HEIGHT}\" \
             font-family=\"sans-serif\" font-size=\"12\">\n"
        ));
        svg.rect((0.0, 0.0), (WIDTH, HEIGHT), r#"fill="white""#);
        // 17 px, smaller for a title that would not fit the width (a bold sans-serif character
        // is about 0.62 of the font size wide)
        let fits = (WIDTH - 40.0) / (0.62 * self.title.chars().count().max(1) as f64);
        let title_size = fits.min(17.0).floor();
        let title_style = format!(r#"{MIDDLE} font-size="{title_size}" font-weight="bold""#);
        svg.text((WIDTH / 2.0, 30.0), &title_style, &self.title);
        for (fraction, label) in x_axis.ticks() {
            let (x, length) = (x_pixel(fraction), if label.is_some() { 6.0 } else { 3.0 });
            svg.line((x, BOTTOM), (x, BOTTOM + length), "black");
            if let Some(label) = label {
                svg.line((x, TOP), (x, BOTTOM), "#e4e4e4");
                svg.text((x, BOTTOM + 20.0), MIDDLE, &label);
            }
        }
        for (fraction, label) in y_axis.ticks() {
            let (y, length) = (y_pixel(fraction), if label.is_some() { 6.0 } else { 3.0 });
            svg.line((LEFT - length, y), (LEFT, y), "black");
            if let Some(label) = label {
                svg.line((LEFT, y), (RIGHT, y), "#e4e4e4");
                svg.text((LEFT - 9.0, y + 4.0), r#"text-anchor="end""#, &label);
            }
        }
        let plot_size = (RIGHT - LEFT, BOTTOM - TOP);
        svg.rect((LEFT, TOP), plot_size, r#"fill="none" stroke="black""#);
        let axis_style = format!(r#"{MIDDLE} font-size="14""#);
        let under_x_axis = ((LEFT + RIGHT) / 2.0, BOTTOM + 46.0);
        svg.text(under_x_axis, &axis_style, &self.x_label);
        // Rotated about its own anchor, so that the y label reads upwards beside the axis.
        let middle = (TOP + BOTTOM) / 2.0;
        let rotated = format!(r#"{axis_style} transform="rotate(-90 24 {middle})""#);
        svg.text((24.0, middle), &rotated, &self.y_label);

        for (i, series) in self.series.iter().enumerate() {
            let [r, g, b] = PALETTE[i % PALETTE.len()];
            let colour = format!("#{r:02X}{g:02X}{b:02X}");
            let to_pixel = |&(x, y): &(f64, f64)| {
                Some((x_pixel(x_axis.fraction(x)?), y_pixel(y_axis.fraction(y)?)))
            };
            let pixels: Vec<(f64, f64)> = series.points.iter().filter_map(to_pixel).collect();
            let point = |(x, y): &(f64, f64)| format!("{x:.1},{y:.1}");
            let points = pixels.iter().map(point).collect::<Vec<_>>().join(" ");
            // past the eight colours, the same colours again with another dash pattern
            let dash = [
                "",
                r#" stroke-dasharray="7 4""#,
                r#" stroke-dasharray="2 3""#,
            ][(i / PALETTE.len()) % 3];
            let style = format!(r#"fill="none" stroke="{colour}" stroke-width="2"{dash}"#);
            svg.0 += &format!("<polyline points=\"{points}\" {style}/>\n");
            for (x, y) in pixels {
                svg.0 += &format!(r#"<circle cx="{x:.1}" cy="{y:.1}" r="3.5" fill="{colour}"/>"#);
                svg.0 += "\n";
            }
            // Legend entry: a colour swatch, then the label.
            let (x, y) = (RIGHT + 15.0, TOP + 22.0 * i as f64);
            let swatch = format!(r#"stroke="{colour}" stroke-width="3"{dash}"#);
            svg.0 += &format!(
                "<line x1=\"{:.1}\" y1=\"{:.1}\" x2=\"{:.1}\" y2=\"{:.1}\" {swatch}/>\n",
                x - 4.0,
                y + 7.0,
                x + 18.0,
                y + 7.0
            );
            svg.text((x + 22.0, y + 11.0), "", &shorten(&series.label));
        }
        svg.0 + "</svg>\n"
    }

    /// The chart rasterised to PNG bytes (resvg, with the system's sans-serif font for text).
    pub fn to_png(&self) -> anyhow::Result<Vec<u8>> {
        let mut options = resvg::usvg::Options::default();
        let fonts = options.fontdb_mut();
        fonts.load_system_fonts();
        // fontdb maps sans-serif to Arial; use a sans face this machine has
        let installed = |name: &str| {
            fonts
                .faces()
                .any(|face| face.families.iter().any(|(family, _)| family == name))
        };
        let family = ["DejaVu Sans", "Liberation Sans", "Noto Sans", "Arial"]
            .into_iter()
            .find(|name| installed(name))
            .map(str::to_string)
            .or_else(|| Some(fonts.faces().next()?.families.first()?.0.clone()));
        if let Some(family) = family {
            fonts.set_sans_serif_family(family);
        }
        let tree = resvg::usvg::Tree::from_str(&self.to_svg(), &options)?;
        let size = tree.size().to_int_size();
        let mut pixmap = resvg::tiny_skia::Pixmap::new(size.width(), size.height())
            .ok_or_else(|| anyhow::anyhow!("chart has an empty size"))?;
        resvg::render(&tree, Default::default(), &mut pixmap.as_mut());
        Ok(pixmap.encode_png()?)
    }
}

struct Svg(String);

impl Svg {
    fn line(&mut self, (x1, y1): (f64, f64), (x2, y2): (f64, f64), stroke: &str) {
        let ends = format!(r#"x1="{x1:.1}" y1="{y1:.1}" x2="{x2:.1}" y2="{y2:.1}""#);
        self.0 += &format!("<line {ends} stroke=\"{stroke}\"/>\n");
    }

    fn rect(&mut self, (x, y): (f64, f64), (width, height): (f64, f64), style: &str) {
        let corners = format!(r#"x="{x}" y="{y}" width="{width}" height="{height}""#);
        self.0 += &format!("<rect {corners} {style}/>\n");
    }

    /// A text element; the content is always escaped.
    fn text(&mut self, (x, y): (f64, f64), attributes: &str, content: &str) {
        let content = escape(content);
        self.0 += &format!("<text x=\"{x:.1}\" y=\"{y:.1}\" {attributes}>{content}</text>\n");
    }
}

/// Where a value sits along its axis (log10 of it on log axes); `None` when it cannot be drawn.
fn plot_space(value: f64, log: bool) -> Option<f64> {
    match log {
        true => (value > 0.0 && value.is_finite()).then(|| value.log10()),
        false => value.is_finite().then_some(value),
    }
}

/// One axis, with its range in plotting space.
struct Axis {
    log: bool,
    lo: f64,
    hi: f64,
    /// Spacing of the labelled ticks in plotting space (one decade on a log axis).
    step: f64,
}

impl Axis {
    /// The range of the drawable values, padded by 5%; an empty or flat range is widened.
    /// A linear range is then widened to multiples of its tick step.
    fn fit(values: impl Iterator<Item = f64>, log: bool) -> Axis {
        let (mut lo, mut hi) = (f64::INFINITY, f64::NEG_INFINITY);
        for s in values.filter_map(|v| plot_space(v, log)) {
            (lo, hi) = (lo.min(s), hi.max(s));
        }
        if lo > hi {
            (lo, hi) = (0.0, 1.0); // nothing to draw: any range will do (1..10 on a log axis)
        }
        let pad = match (lo < hi, log) {
            (true, _) => 0.05 * (hi - lo),
            (false, true) => 0.5,
            (false, false) => 0.1 * lo.abs().max(1.0),
        };
        let (mut lo, mut hi) = (lo - pad, hi + pad);
        // Two labelled powers of ten make a log axis readable: else widen to whole decades.
        if log && lo.ceil() + 1.0 > hi.floor() {
            (lo, hi) = (lo.floor(), hi.ceil());
        }
        let step = if log { 1.0 } else { nice_step(lo, hi) };
        if !log {
            (lo, hi) = ((lo / step).floor() * step, (hi / step).ceil() * step);
        }
        Axis { log, lo, hi, step }
    }

    /// How far along the axis (0 to 1) a data value lies; `None` when it cannot be drawn.
    fn fraction(&self, value: f64) -> Option<f64> {
        plot_space(value, self.log).map(|s| (s - self.lo) / (self.hi - self.lo))
    }

    /// Ticks as fractions along the axis; major ticks carry a label, minor ones `None`.
    fn ticks(&self) -> Vec<(f64, Option<String>)> {
        let mut ticks = Vec::new(); // (position in plotting space, label)
        if self.log {
            let (first, last) = (self.lo.floor() as i32, self.hi.ceil() as i32);
            // Label every decade up to ten of them, then thin out so that labels do not collide.
            let stride = (last - first) / 10 + 1;
            for e in first..=last {
                let label = (e.rem_euclid(stride) == 0).then(|| power_of_ten(e));
                ticks.push((e as f64, label));
                if stride == 1 {
                    ticks.extend((2..=9).map(|m| (e as f64 + f64::from(m).log10(), None)));
                }
            }
            ticks.retain(|(s, _)| (self.lo..=self.hi).contains(s));
        } else {
            let decimals = (-self.step.log10().floor()).max(0.0) as usize;
            // Integer multiples of the step, so that labels carry no accumulated rounding.
            let (first, last) = ((self.lo / self.step).round(), (self.hi / self.step).round());
            for i in first as i64..=last as i64 {
                let value = i as f64 * self.step;
                ticks.push((value, Some(format!("{value:.decimals$}"))));
            }
        }
        let fraction = |s: f64| (s - self.lo) / (self.hi - self.lo);
        ticks
            .into_iter()
            .map(|(s, label)| (fraction(s), label))
            .collect()
    }
}

/// The 1, 2 or 5 x 10^k step that gives closest to 6.5 ticks (so 5 to 8 nearly always) once
/// the range is widened to multiples of it.
fn nice_step(lo: f64, hi: f64) -> f64 {
    let count = |step: f64| (hi / step).ceil() - (lo / step).floor() + 1.0;
    let misfit = |step: &f64| (count(*step) - 6.5).abs();
    let magnitude = (hi - lo).log10().floor() as i32;
    (magnitude - 2..=magnitude)
        .flat_map(|e| [1.0, 2.0, 5.0].map(|m| m * 10f64.powi(e)))
        .min_by(|a, b| misfit(a).total_cmp(&misfit(b)))
        .expect("there are candidate steps")
}

/// 10^e as a plain decimal ("0.01", "1000"), written out to avoid rounding noise.
fn power_of_ten(e: i32) -> String {
    match e {
        0.. => format!("1{}", "0".repeat(e as usize)),
        _ => format!("0.{}1", "0".repeat((-e - 1) as usize)),
    }
}

/// The label, cut to `LEGEND_CHARS` characters.
fn shorten(label: &str) -> String {
    match label.chars().count() > LEGEND_CHARS {
        true => label.chars().take(LEGEND_CHARS - 1).chain(['…']).collect(),
        false => label.to_string(),
    }
}

fn escape(text: &str) -> String {
    let text = text.replace('&', "&amp;").replace('<', "&lt;");
    text.replace('>', "&gt;").replace('"', "&quot;")
}

#[cfg(test)]
mod tests {
    use super::*;

    fn chart(log: bool, series: &[(&str, &[(f64, f64)])]) -> Chart {
        let to_series = |&(label, points): &(&str, &[(f64, f64)])| Series {
            label: label.into(),
            points: points.to_vec(),
        };
        let series = series.iter().map(to_series).collect();
        let (title, x_label, y_label) = ("t".into(), "x".into(), "y".into());
        Chart {
            title,
            x_label,
            y_label,
            x_log: log,
            y_log: log,
            series,
        }
    }

    /// The pixel coordinates of every polyline, in document order.
    fn polylines(svg: &str) -> Vec<Vec<(f64, f64)>> {
        let number = |n: &str| n.parse::<f64>().unwrap();
        let point = |p: &str| {
            let (x, y) = p.split_once(',').unwrap();
            (number(x), number(y))
        };
        let points = |rest: &str| {
            rest.split('"')
                .nth(1)
                .unwrap()
                .split(' ')
                .map(point)
                .collect()
        };
        svg.split("<polyline points=").skip(1).map(points).collect()
    }

    #[test]
    fn log_log_series_map_inside_the_plot_in_data_order() {
        let fast: &[(f64, f64)] = &[(0.1, 50.0), (1.0, 5.0), (10.0, 0.5)];
        let slow: &[(f64, f64)] = &[(0.3, 20.0), (3.0, 0.2), (200.0, 0.01)];
        let svg = chart(true, &[("fast solver", fast), ("slow solver", slow)]).to_svg();
        assert!(svg.contains(">fast solver<") && svg.contains(">slow solver<"));
        let lines = polylines(&svg);
        assert_eq!(lines.iter().map(Vec::len).collect::<Vec<_>>(), [3, 3]);
        let inside =
            |&(x, y): &(f64, f64)| (LEFT..=RIGHT).contains(&x) && (TOP..=BOTTOM).contains(&y);
        assert!(lines.iter().flatten().all(inside), "{lines:?}");
        // x grows and y falls along the data, so pixel x and pixel y (downwards) both grow.
        let growing = |w: &[(f64, f64)]| w[0].0 < w[1].0 && w[0].1 < w[1].1;
        assert!(
            lines.iter().all(|line| line.windows(2).all(growing)),
            "{lines:?}"
        );
    }

    #[test]
    fn log_ticks_label_each_power_of_ten_in_range() {
        let ticks = Axis::fit([0.03, 250.0].into_iter(), true).ticks();
        let labels: Vec<String> = ticks.into_iter().filter_map(|(_, label)| label).collect();
        assert_eq!(labels, ["0.1", "1", "10", "100"]);
    }

    #[test]
    fn undrawable_empty_and_flat_data_never_produce_nan() {
        let mixed: &[(f64, f64)] = &[(0.0, 1.0), (-1.0, 2.0), (1.0, 0.0), (2.0, 3.0)];
        let flat: &[(f64, f64)] = &[(2.0, 7.0), (2.0, 7.0)];
        let charts = [
            chart(true, &[("mixed", mixed)]),
            chart(true, &[("undrawable", &[(0.0, -1.0)])]),
            chart(false, &[]),
            chart(false, &[("flat", flat)]),
        ];
        for svg in charts.map(|chart| chart.to_svg()) {
            assert!(!svg.contains("NaN") && !svg.contains("inf"), "{svg}");
            assert!(svg.starts_with("<svg xmlns=\"http://www.w3.org/2000/svg\""));
            assert!(svg.ends_with("</svg>\n"));
        }
    }

    #[test]
    fn text_is_escaped() {
        let mut chart = chart(false, &[("<a & \"b\">", &[(1.0, 2.0)])]);
        chart.title = "x < y & z > w".into();
        let svg = chart.to_svg();
        assert!(svg.contains(">x &lt; y &amp; z &gt; w<"));
        assert!(svg.contains(">&lt;a &amp; &quot;b&quot;&gt;<"));
    }

    /// A short title is drawn at 17 px; a long one (a sweep's, with the machine's full name)
    /// smaller, so that its estimated width stays within the chart's.
    #[test]
    fn a_long_title_is_drawn_small_enough_to_fit() {
        let title_size = |title: &str| {
            let mut chart = chart(false, &[("a", &[(1.0, 2.0)])]);
            chart.title = title.into();
            let svg = chart.to_svg();
            let title_text = svg
                .lines()
                .find(|l| l.contains(&format!(">{title}<")))
                .unwrap();
            let size = title_text.split("font-size=\"").nth(1).unwrap();
            size[..size.find('"').unwrap()].parse::<f64>().unwrap()
        };
        assert_eq!(title_size("short"), 17.0);
        let long = "w".repeat(140);
        let size = title_size(&long);
        assert!(size < 17.0 && 0.62 * size * 140.0 <= WIDTH - 40.0, "{size}");
    }
}
