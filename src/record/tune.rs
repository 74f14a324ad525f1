//! The tuning grid's recording (`rodlab tune`, [`crate::tune`]), one file for every setting.
//!
//! Entity paths, with `<copy>` = `bend_<row>/twist_<column>/iter_<layer>`:
//! - `tune/grid/<copy>/capsules|spheres|boxes`: the copy's bodies, one batch per copy, in the
//!   copy's colour (hue by twist column, lightness by bend row);
//! - `tune/grid/<copy>/label`: the copy's settings as a label above it;
//! - `tune/grid/<copy>/rod`: the rod's centerline, coloured by its bend (blue straight, red at
//!   pi/2 or more);
//! - `tune/psi/<copy>`, `tune/tau/<copy>` (rad) and `tune/energy/<copy>` (J) over `frame`: a
//!   view with origin `tune/psi/bend_<row>` overlays a row; the blueprint's column views list
//!   a column's copies;
//! - `tune/chart`: the summary chart; `tune/table`: the summary CSV.
//!
//! Every shard writes the same recording id and the blueprint of the whole grid, so the shards'
//! files merge into one recording (`rerun rrd merge`).

use std::path::Path;

use rerun::blueprint::{
    Blueprint, ContainerLike, Horizontal, Spatial2DView, Spatial3DView, Tabs, TextDocumentView,
    TimeSeriesView, Vertical,
};
use rerun::RecordingStream;

use super::bodies::{body_batches, log_shapes, pose_track_kind, shape_poses, BodyBatch};
use super::tracks::Track;
use super::{create_parent, APPLICATION_ID};
use crate::constraint::Constraint;
use crate::lab::Lab;
use crate::tune::{Copy, Trace, TuneRow};

/// Points along each drawn centerline.
const CENTERLINE_SAMPLES: usize = 16;

/// The copy's colour: hue by twist column, lightness by bend row, so both a row's and a
/// column's overlaid plots tell their lines apart.
pub fn copy_color(copy: &Copy, rows: usize, columns: usize) -> rerun::Color {
    let hue = 300.0 * copy.column as f32 / columns.max(2).saturating_sub(1) as f32;
    let lightness = 0.3 + 0.35 * copy.row as f32 / rows.max(2).saturating_sub(1) as f32;
    let [r, g, b] = hsl(hue, 0.75, lightness);
    rerun::Color::from_rgb(r, g, b)
}

fn hsl(hue: f32, saturation: f32, lightness: f32) -> [u8; 3] {
    let c = (1.0 - (2.0 * lightness - 1.0).abs()) * saturation;
    let h = hue / 60.0;
    let x = c * (1.0 - (h % 2.0 - 1.0).abs());
    let (r, g, b) = match h as u32 {
        0 => (c, x, 0.0),
        1 => (x, c, 0.0),
        2 => (0.0, c, x),
        3 => (0.0, x, c),
        4 => (x, 0.0, c),
        _ => (c, 0.0, x),
    };
    let m = lightness - 0.5 * c;
    [r, g, b].map(|v| (255.0 * (v + m)).round().clamp(0.0, 255.0) as u8)
}

/// The rod's colour at bend `psi`: blue straight to red at pi/2.
fn bend_color(psi: f32) -> rerun::Color {
    let t = (psi / std::f32::consts::FRAC_PI_2).clamp(0.0, 1.0);
    let mix = |a: f32, b: f32| (a + t * (b - a)).round() as u8;
    rerun::Color::from_rgb(mix(60.0, 230.0), mix(110.0, 50.0), mix(230.0, 40.0))
}

/// The layout: the grid beside the plots, one tab per bend row and per twist column.
fn blueprint(all: &[Copy]) -> Blueprint {
    let rows = all.iter().map(|c| c.row).max().map_or(0, |r| r + 1);
    let columns = all.iter().map(|c| c.column).max().map_or(0, |c| c + 1);
    let row_label = |row: usize| {
        all.iter()
            .find(|c| c.row == row)
            .unwrap()
            .bend
            .label("bend")
    };
    let column_label = |column: usize| {
        (all.iter().find(|c| c.column == column).unwrap())
            .twist
            .label("twist")
    };
    let by_row = |quantity: &str| {
        Tabs::new((0..rows).map(|row| {
            ContainerLike::from(
                TimeSeriesView::new(format!("{quantity}, {}", row_label(row)))
                    .with_origin(format!("tune/{quantity}/bend_{row}")),
            )
        }))
    };
    let by_column = |quantity: &str| {
        Tabs::new((0..columns).map(|column| {
            let contents =
                (0..rows).map(|row| format!("+ /tune/{quantity}/bend_{row}/twist_{column}/**"));
            ContainerLike::from(
                TimeSeriesView::new(format!("{quantity}, {}", column_label(column)))
                    .with_origin(format!("tune/{quantity}"))
                    .with_contents(contents),
            )
        }))
    };
    let plots = Vertical::new([
        ContainerLike::from(by_row("psi")),
        ContainerLike::from(by_column("tau")),
        ContainerLike::from(Tabs::new([
            ContainerLike::from(by_column("psi")),
            ContainerLike::from(by_row("tau")),
            ContainerLike::from(TimeSeriesView::new("energy (J)").with_origin("tune/energy")),
        ])),
    ]);
    let left = Tabs::new([
        ContainerLike::from(Spatial3DView::new("Tuning grid").with_origin("tune/grid")),
        ContainerLike::from(Spatial2DView::new("Summary chart").with_origin("tune/chart")),
        ContainerLike::from(TextDocumentView::new("Summary table").with_origin("tune/table")),
    ]);
    Blueprint::new(
        Horizontal::new([ContainerLike::from(left), ContainerLike::from(plots)])
            .with_column_shares([0.55, 0.45]),
    )
    .with_auto_views(false)
}

/// Streams the grid of one `rodlab tune` run (or shard) into a recording.
pub struct TuneRecorder {
    rec: RecordingStream,
    /// This shard's copies, in the order of the labs the observer gets.
    copies: Vec<Copy>,
    rows: usize,
    columns: usize,
    batches: Vec<Vec<BodyBatch>>,
    /// One pose track per batch, sent every 60 frames.
    poses: Vec<Vec<Track>>,
    points: Vec<[f32; 3]>,
}

impl TuneRecorder {
    /// Opens `path` for the copies `mine` of the grid `all` of scene `scene`.
    pub fn create(path: &Path, scene: &str, all: &[Copy], mine: &[Copy]) -> anyhow::Result<Self> {
        create_parent(path)?;
        let builder = rerun::RecordingStreamBuilder::new(APPLICATION_ID)
            .recording_name(format!("{scene}_tune"))
            .recording_id(format!("rodlab-tune-{scene}"))
            .with_blueprint(blueprint(all));
        let rec = super::file::save(builder, path, true)?;
        rec.set_log_time_enabled(false);
        Ok(TuneRecorder {
            rec,
            copies: mine.to_vec(),
            rows: all.iter().map(|c| c.row).max().map_or(1, |r| r + 1),
            columns: all.iter().map(|c| c.column).max().map_or(1, |c| c + 1),
            batches: Vec::new(),
            poses: Vec::new(),
            points: Vec::new(),
        })
    }

    /// The copies' poses and rods at `frame` (frame 0: also their shapes and labels).
    pub fn frame(&mut self, frame: u64, labs: &[Option<&Lab>]) -> anyhow::Result<()> {
        if frame == 0 {
            self.log_static(labs)?;
        }
        let rec = &self.rec;
        rec.set_time_sequence("frame", frame as i64);
        let copies = self.copies.iter().zip(labs);
        for ((copy, lab), (batches, tracks)) in copies.zip(self.batches.iter().zip(&mut self.poses))
        {
            let Some(lab) = lab else { continue };
            let world = &lab.world;
            rec.set_duration_secs("sim_time", world.time);
            for (batch, track) in batches.iter().zip(tracks.iter_mut()) {
                track.begin(frame as i64, world.time);
                for (centre, rotation) in shape_poses(world, batch) {
                    track.push_pose(centre, rotation);
                }
            }
            for constraint in &world.constraints {
                let Constraint::Rod(rod) = constraint else {
                    continue;
                };
                let (a, b) = (world.body(rod.body_a), world.body(rod.body_b));
                self.points.clear();
                let last = (CENTERLINE_SAMPLES - 1) as f32;
                self.points.extend(
                    (0..CENTERLINE_SAMPLES).map(|i| rod.sample(a, b, i as f32 / last).0.to_array()),
                );
                let psi = rod.state(a, b).psi;
                rec.log(
                    format!("tune/grid/{}/rod", copy.entity()),
                    &rerun::LineStrips3D::new([self.points.iter().copied()])
                        .with_colors([bend_color(psi)])
                        .with_radii([0.02]),
                )?;
            }
        }
        if frame.is_multiple_of(60) {
            self.send_poses()?;
            super::file::flush(&self.rec)?;
        }
        Ok(())
    }

    fn send_poses(&mut self) -> anyhow::Result<()> {
        for track in self.poses.iter_mut().flatten() {
            track.send(&self.rec)?;
        }
        Ok(())
    }

    fn log_static(&mut self, labs: &[Option<&Lab>]) -> anyhow::Result<()> {
        let rec = &self.rec;
        rec.log_static("tune/grid", &rerun::ViewCoordinates::RIGHT_HAND_Y_UP())?;
        for (copy, lab) in self.copies.iter().zip(labs) {
            let Some(lab) = lab else {
                self.batches.push(Vec::new());
                self.poses.push(Vec::new());
                continue;
            };
            let entity = copy.entity();
            let batches = body_batches(lab, |_| format!("tune/grid/{entity}"));
            let color = copy_color(copy, self.rows, self.columns);
            for batch in &batches {
                log_shapes(rec, &lab.world, batch, vec![color; batch.bodies.len()])?;
            }
            let kind = |b: &BodyBatch| pose_track_kind(&lab.world, b);
            (self.poses).push(
                batches
                    .iter()
                    .map(|b| Track::new(b.entity.clone(), kind(b)))
                    .collect(),
            );
            self.batches.push(batches);
            let top = (lab.world.bodies.iter())
                .map(|b| b.position)
                .fold(copy.offset, |top, p| if p.y > top.y { p } else { top });
            rec.log_static(
                format!("tune/grid/{entity}/label"),
                &rerun::Points3D::new([(top + crate::math::Vec3::Y * 0.35).to_array()])
                    .with_labels([copy.label()])
                    .with_colors([color])
                    .with_radii([0.01])
                    .with_show_labels(true),
            )?;
            for quantity in ["psi", "tau", "energy"] {
                rec.log_static(
                    format!("tune/{quantity}/{entity}"),
                    &rerun::SeriesLines::new()
                        .with_colors([color])
                        .with_names([copy.label()]),
                )?;
            }
        }
        Ok(())
    }

    /// The copies' series (as columns over `frame`), the summary table and chart; flushes.
    pub fn finish(
        mut self,
        traces: &[Trace],
        rows: &[TuneRow],
        csv: &str,
        chart_png: &[u8],
    ) -> anyhow::Result<()> {
        self.send_poses()?;
        let rec = &self.rec;
        for (copy, trace) in self.copies.iter().zip(traces) {
            let entity = copy.entity();
            let frames = || rerun::TimeColumn::new_sequence("frame", 1..=trace.psi.len() as i64);
            for (quantity, values) in [
                ("psi", &trace.psi),
                ("tau", &trace.tau),
                ("energy", &trace.energy),
            ] {
                rec.send_columns(
                    format!("tune/{quantity}/{entity}"),
                    [frames()],
                    rerun::Scalars::new(values.iter().map(|&v| v as f64))
                        .columns_of_unit_batches()?,
                )?;
            }
        }
        let failed: Vec<String> = (rows.iter())
            .filter_map(|r| Some(format!("- {}: {}", r.copy.label(), r.failed.as_ref()?)))
            .collect();
        let failures = if failed.is_empty() {
            String::new()
        } else {
            format!("\n\nStopped early:\n{}\n", failed.join("\n"))
        };
        rec.log_static(
            "tune/table",
            &rerun::TextDocument::from_markdown(format!(
                "# Tuning summary\n\n```\n{csv}```{failures}\n"
            )),
        )?;
        rec.log_static(
            "tune/chart",
            &rerun::EncodedImage::from_file_contents(chart_png.to_vec()),
        )?;
        super::file::finish(rec)
    }
}
