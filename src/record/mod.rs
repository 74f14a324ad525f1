//! Recording to Rerun: the only module that uses `rerun`.
//!
//! Entity paths (documented in the README):
//! - `world/<group>/capsules|spheres|boxes`: one batched archetype per group (a ragdoll, or
//!   `props` for free bodies); shapes logged once as static data, per-instance translations and
//!   quaternions every frame;
//! - `world/<group>/joints`: both world anchors of every joint (Points3D, 2 per joint);
//! - `world/<ragdoll>/rod/<rod>/centerline` (LineStrips3D, gamma(s) sampled, ends at the body
//!   centres) and `.../frames` (Arrows3D: material normal and binormal along the arc);
//! - `world/<ragdoll>/bones/<method>`: the animation bones (LineStrips3D through their origins);
//! - `metrics/rod/{psi,tau,length_violation_cm,curve_violation_rad}`: one instance per rod;
//! - `metrics/bones/<method>/{length_error_cm,chest_gap_cm}`: one instance per ragdoll;
//! - `metrics/dislocation_cm`, `metrics/angular_rad`, `metrics/pose_deviation_cm`: residual
//!   scalars, one entity per measure with one instance (a named line) per ragdoll, so spines
//!   compare in one plot;
//! - `metrics/energy/{kinetic,potential,total}`: energy (J);
//! - `metrics/awake_bodies`: dynamic bodies awake, with sleeping on (sleeping bodies are drawn
//!   in their colour faded toward grey);
//! - `scene`: the scene file (static), `failure`: why a run stopped early, if it did,
//!   `state_hash`: the final state's hash (static text, 16 hex digits) after a whole run.
//!
//! Timelines: `frame` (sequence, 0 = initial state) and `sim_time` (seconds).
//!
//! Per-frame data is buffered and sent once per simulated second, one chunk per entity
//! (`recorder`, `tracks`, `columns`); static data is logged once.

use std::path::Path;

use rerun::blueprint::{
    Blueprint, ContainerLike, Horizontal, Spatial3DView, Tabs, TextDocumentView, TimeSeriesView,
    Vertical,
};
use rerun::RecordingStream;

use crate::body::BodyId;
use crate::lab::Lab;
use crate::math::{Quat, Vec3};
use crate::scene::Scene;
use crate::shape::Shape;
use crate::world::World;

mod columns;
mod recorder;
mod tracks;
pub mod tune;

pub use recorder::Recorder;

use tracks::TrackKind;

/// Application id of every rodlab recording.
pub const APPLICATION_ID: &str = "rodlab";

/// Flush the sink once this much simulated time (s) has passed since the last flush, so a
/// killed run loses at most that much of the simulation; chunks then fall on the same frames
/// on every machine.
const FLUSH_EVERY_S: f64 = 1.0;
/// ... or this much wall time (s), so a slow run (many ragdolls) also shows up in the file as
/// it goes. Each flush cuts a chunk per entity, so not more often.
const FLUSH_WALL_S: f64 = 5.0;
/// A flush that takes longer than this (s) fails the run instead of hanging it: the file
/// writer has died or stalled (a full disk, a vanished file system).
const FLUSH_TIMEOUT_S: u64 = 10;

/// Flushes `rec`, at most [`FLUSH_TIMEOUT_S`] long.
fn flush(rec: &RecordingStream) -> anyhow::Result<()> {
    rec.flush_with_timeout(std::time::Duration::from_secs(FLUSH_TIMEOUT_S))
        .map_err(|e| {
            anyhow::anyhow!(
                "the recording could not be written ({e}); is the disk full, or the file gone?"
            )
        })
}

/// The layout for a scene: the 3D view beside its plots (residuals, then tabs for energy, pose
/// deviation, rod scalars and bone errors; for the kinematics scene, the end gaps).
pub fn blueprint(scene: &Scene) -> Blueprint {
    let series = |name: &str, origin: &str| {
        ContainerLike::from(TimeSeriesView::new(name).with_origin(origin))
    };
    let plots = if scene.def.kinematics.is_some() {
        Vertical::new([
            series("End gap from the rod (cm)", "metrics/end_gap_cm"),
            series("Bend (rad)", "metrics/bend_rad"),
        ])
    } else {
        let more = Tabs::new([
            series("Energy (J)", "metrics/energy"),
            series("Pose deviation (cm)", "metrics/pose_deviation_cm"),
            series("Rod", "metrics/rod"),
            series("Bones (cm)", "metrics/bones"),
            series("Totals", "metrics/total"),
            series("Penetration (cm)", "metrics/penetration_cm"),
            series("Overlap found afresh (cm)", "metrics/overlap_cm"),
            series("Awake bodies", "metrics/awake_bodies"),
        ]);
        Vertical::new([
            series("Dislocation (cm)", "metrics/dislocation_cm"),
            series("Angular violation (rad)", "metrics/angular_rad"),
            ContainerLike::from(more),
        ])
    };
    let left = Tabs::new([
        ContainerLike::from(Spatial3DView::new("Scene").with_origin("world")),
        ContainerLike::from(TextDocumentView::new("Scene file").with_origin("scene")),
    ]);
    Blueprint::new(
        Horizontal::new([ContainerLike::from(left), ContainerLike::from(plots)])
            .with_column_shares([0.6, 0.4]),
    )
    .with_auto_views(false)
}

/// Creates the folder `path` will be written in, if it has one.
fn create_parent(path: &Path) -> anyhow::Result<()> {
    if let Some(dir) = path.parent().filter(|d| !d.as_os_str().is_empty()) {
        std::fs::create_dir_all(dir)?;
    }
    Ok(())
}

/// Opens a recording of `scene` that writes to `path` (creating its folder), with its blueprint
/// (and the footer unless `[record] footer = false`).
pub fn save_to(path: &Path, scene: &Scene) -> anyhow::Result<RecordingStream> {
    create_parent(path)?;
    let rec = rerun::RecordingStreamBuilder::new(APPLICATION_ID)
        .recording_name(scene.name())
        .with_blueprint(blueprint(scene));
    let rec = if scene.def.record.footer {
        rec.save(path)?
    } else {
        let options = rerun::sink::FileSinkOptions {
            write_footer: false,
        };
        rec.set_sinks((rerun::sink::FileSink::with_options(path, options)?,))?
    };
    Ok(rec)
}

/// Which bodies one batched entity draws, and how.
struct BodyBatch {
    entity: String,
    bodies: Vec<BodyId>,
    /// Capsules: body-space offset of the first cap centre and rotation taking +Z to the axis.
    local_offsets: Vec<(Vec3, Quat)>,
    translations: Vec<[f32; 3]>,
    rotations: Vec<rerun::Quaternion>,
    /// With sleeping on, the awake colours, and the sleep state last logged (colours are then
    /// logged per frame when a body's state changes, instead of once as static data).
    colors: Vec<rerun::Color>,
    logged_asleep: Vec<bool>,
}

/// Body shapes take their colours as static data, unless the colours are per frame (empty).
trait WithColors: Sized {
    fn colors(self, colors: Vec<rerun::Color>) -> Self;
}

macro_rules! with_colors {
    ($($t:ty),*) => {$(
        impl WithColors for $t {
            fn colors(self, colors: Vec<rerun::Color>) -> Self {
                self.with_colors(colors)
            }
        }
    )*};
}
with_colors!(rerun::Capsules3D, rerun::Ellipsoids3D, rerun::Boxes3D);

fn with_colors_if_any<T: WithColors>(shapes: T, colors: Vec<rerun::Color>) -> T {
    if colors.is_empty() {
        shapes
    } else {
        shapes.colors(colors)
    }
}

/// With sleeping on, the batch's colours when any body's sleep state changed since they were
/// last logged (sleeping bodies faded); empty otherwise.
fn sleep_colors(batch: &mut BodyBatch, world: &crate::world::World) -> Vec<rerun::Color> {
    if batch.colors.is_empty() {
        return Vec::new();
    }
    let asleep = batch.bodies.iter().map(|&id| world.body(id).is_asleep());
    if batch.logged_asleep.len() == batch.bodies.len()
        && asleep.clone().eq(batch.logged_asleep.iter().copied())
    {
        return Vec::new();
    }
    batch.logged_asleep.clear();
    batch.logged_asleep.extend(asleep);
    (batch.colors.iter().zip(&batch.logged_asleep))
        .map(|(&c, &asleep)| if asleep { asleep_color(c) } else { c })
        .collect()
}

/// A sleeping body's colour: its own, faded toward grey.
fn asleep_color(c: rerun::Color) -> rerun::Color {
    let [r, g, b, _] = c.to_array();
    let fade = |x: u8| (x as u16 * 2 / 5 + 90) as u8;
    rerun::Color::from_rgb(fade(r), fade(g), fade(b))
}

/// The lab's bodies in batches, one per group and shape kind: `<group(body)>/capsules`,
/// `.../spheres`, `.../boxes` (half-spaces are drawn apart).
fn body_batches(lab: &Lab, group: impl Fn(BodyId) -> String) -> Vec<BodyBatch> {
    let world = &lab.world;
    let mut batches: Vec<BodyBatch> = Vec::new();
    for (i, body) in world.bodies.iter().enumerate() {
        let id = BodyId(i as u32);
        let kind = match body.shape {
            Shape::Capsule { .. } => "capsules",
            Shape::Sphere { .. } => "spheres",
            Shape::Cuboid { .. } => "boxes",
            Shape::HalfSpace => continue, // static, drawn once in `log_static`
        };
        let entity = format!("{}/{kind}", group(id));
        let offset = match body.shape {
            Shape::Capsule {
                half_height, axis, ..
            } => (
                -half_height * axis.unit(),
                Quat::from_rotation_arc(Vec3::Z, axis.unit()),
            ),
            _ => (Vec3::ZERO, Quat::IDENTITY),
        };
        match batches.iter_mut().find(|b| b.entity == entity) {
            Some(batch) => {
                batch.bodies.push(id);
                batch.local_offsets.push(offset);
            }
            None => batches.push(BodyBatch {
                entity,
                bodies: vec![id],
                local_offsets: vec![offset],
                translations: Vec::new(),
                rotations: Vec::new(),
                colors: Vec::new(),
                logged_asleep: Vec::new(),
            }),
        }
    }
    batches
}

/// A batch's shapes, labelled with the bodies' short names, and its colours (none: per
/// frame), as static data.
fn log_shapes(
    rec: &RecordingStream,
    world: &World,
    batch: &BodyBatch,
    colors: Vec<rerun::Color>,
) -> anyhow::Result<()> {
    let labels: Vec<String> = (batch.bodies.iter())
        .map(|&id| {
            let name = &world.body(id).name;
            name.rsplit('/').next().unwrap_or_default().to_string()
        })
        .collect();
    match world.body(batch.bodies[0]).shape {
        Shape::Capsule { .. } => {
            let (lengths, radii): (Vec<f32>, Vec<f32>) = batch
                .bodies
                .iter()
                .map(|&id| match world.body(id).shape {
                    Shape::Capsule {
                        half_height,
                        radius,
                        ..
                    } => (2.0 * half_height, radius),
                    _ => unreachable!("batches hold one shape kind"),
                })
                .unzip();
            let shapes = rerun::Capsules3D::from_lengths_and_radii(lengths, radii)
                .with_fill_mode(rerun::components::FillMode::Solid)
                .with_labels(labels)
                .with_show_labels(false);
            rec.log_static(batch.entity.as_str(), &with_colors_if_any(shapes, colors))?;
        }
        Shape::HalfSpace => unreachable!("half-spaces are not batched"),
        Shape::Sphere { .. } => {
            let radii: Vec<f32> = batch
                .bodies
                .iter()
                .map(|&id| world.body(id).shape.bounding_radius())
                .collect();
            let shapes = rerun::Ellipsoids3D::from_radii(radii)
                .with_fill_mode(rerun::components::FillMode::Solid)
                .with_labels(labels)
                .with_show_labels(false);
            rec.log_static(batch.entity.as_str(), &with_colors_if_any(shapes, colors))?;
        }
        Shape::Cuboid { .. } => {
            let half_sizes: Vec<[f32; 3]> = batch
                .bodies
                .iter()
                .map(|&id| match world.body(id).shape {
                    Shape::Cuboid { half_extents } => half_extents.to_array(),
                    _ => unreachable!("batches hold one shape kind"),
                })
                .collect();
            let shapes = rerun::Boxes3D::from_half_sizes(half_sizes)
                .with_fill_mode(rerun::components::FillMode::Solid)
                .with_labels(labels)
                .with_show_labels(false);
            rec.log_static(batch.entity.as_str(), &with_colors_if_any(shapes, colors))?;
        }
    }
    Ok(())
}

/// The drawn pose of each of a batch's shapes: centre (a capsule's first cap centre) and
/// rotation (xyzw).
fn shape_poses<'a>(
    world: &'a World,
    batch: &'a BodyBatch,
) -> impl Iterator<Item = ([f32; 3], [f32; 4])> + 'a {
    (batch.bodies.iter().zip(&batch.local_offsets)).map(|(&id, &(offset, axis_rotation))| {
        let body = world.body(id);
        let centre = body.position + body.orientation * offset;
        (centre.to_array(), (body.orientation * axis_rotation).to_array())
    })
}

/// The kind of track a batch's poses go to.
fn pose_track_kind(world: &World, batch: &BodyBatch) -> TrackKind {
    match world.body(batch.bodies[0]).shape {
        Shape::Capsule { .. } => TrackKind::Capsules,
        Shape::Sphere { .. } => TrackKind::Ellipsoids,
        Shape::Cuboid { .. } | Shape::HalfSpace => TrackKind::Boxes,
    }
}

/// A batch's colours (after a sleep state changed), at the current frame.
fn log_colors(
    rec: &RecordingStream,
    world: &World,
    batch: &BodyBatch,
    colors: Vec<rerun::Color>,
) -> anyhow::Result<()> {
    let entity = batch.entity.as_str();
    match pose_track_kind(world, batch) {
        TrackKind::Capsules => {
            rec.log(entity, &rerun::Capsules3D::update_fields().with_colors(colors))?
        }
        TrackKind::Ellipsoids => {
            rec.log(entity, &rerun::Ellipsoids3D::update_fields().with_colors(colors))?
        }
        _ => rec.log(entity, &rerun::Boxes3D::update_fields().with_colors(colors))?,
    }
    Ok(())
}

/// A batch's poses this frame, logged at once (and its colours, if any changed).
fn log_poses(
    rec: &RecordingStream,
    world: &World,
    batch: &mut BodyBatch,
    colors: Vec<rerun::Color>,
) -> anyhow::Result<()> {
    let (mut translations, mut rotations) = (
        std::mem::take(&mut batch.translations),
        std::mem::take(&mut batch.rotations),
    );
    translations.clear();
    rotations.clear();
    for (centre, rotation) in shape_poses(world, batch) {
        translations.push(centre);
        rotations.push(rerun::Quaternion::from_xyzw(rotation));
    }
    (batch.translations, batch.rotations) = (translations, rotations);
    let entity = batch.entity.as_str();
    match world.body(batch.bodies[0]).shape {
        Shape::Capsule { .. } => rec.log(
            entity,
            &with_colors_if_any(
                rerun::Capsules3D::update_fields()
                    .with_translations(batch.translations.iter().copied())
                    .with_quaternions(batch.rotations.iter().copied()),
                colors,
            ),
        )?,
        Shape::HalfSpace => unreachable!("half-spaces are not batched"),
        Shape::Sphere { .. } => rec.log(
            entity,
            &with_colors_if_any(
                rerun::Ellipsoids3D::update_fields()
                    .with_centers(batch.translations.iter().copied())
                    .with_quaternions(batch.rotations.iter().copied()),
                colors,
            ),
        )?,
        Shape::Cuboid { .. } => rec.log(
            entity,
            &with_colors_if_any(
                rerun::Boxes3D::update_fields()
                    .with_centers(batch.translations.iter().copied())
                    .with_quaternions(batch.rotations.iter().copied()),
                colors,
            ),
        )?,
    }
    Ok(())
}

/// Records the kinematics comparison (Fig. 6): the three end loci as static line strips, and per
/// frame the three spines at one bend with the end gaps. Returns the largest gaps (m) of the
/// equal and the unequal chain from the rod.
pub fn record_kinematics(rec: &RecordingStream, scene: &Scene) -> anyhow::Result<(f32, f32)> {
    use crate::kinematics::{chain_points, equal_weights, rod_points};
    let k = scene.def.kinematics.as_ref().expect("a kinematics scene");
    rec.set_log_time_enabled(false);
    rec.log_static("world", &rerun::ViewCoordinates::RIGHT_HAND_Y_UP())?;
    let text = format!("# {}\n\n```toml\n{}\n```\n", scene.name(), scene.text);
    rec.log_static("scene", &rerun::TextDocument::from_markdown(text))?;
    let total: f32 = k.unequal.iter().sum();
    let unequal: Vec<f32> = k.unequal.iter().map(|w| w / total).collect();
    let equal = equal_weights(k.joints);
    let max_bend = k.max_bend.to_radians();
    let frames = scene.def.frames.max(2) as usize;
    let bend = |i: usize| -max_bend + 2.0 * max_bend * i as f32 / (frames - 1) as f32;
    let spines: [(&str, rerun::Color); 3] = [
        ("equal_chain", rerun::Color::from_rgb(60, 110, 220)),
        ("unequal_chain", rerun::Color::from_rgb(60, 170, 90)),
        ("rod", rerun::Color::from_rgb(220, 60, 50)),
    ];
    let shape = |name: &str, psi: f32| match name {
        "equal_chain" => chain_points(k.length, psi, &equal),
        "unequal_chain" => chain_points(k.length, psi, &unequal),
        _ => rod_points(k.length, psi, 32),
    };
    for (name, color) in spines {
        let locus: Vec<[f32; 3]> = (0..frames)
            .map(|i| shape(name, bend(i)).last().unwrap().to_array())
            .collect();
        rec.log_static(
            format!("world/locus/{name}"),
            &rerun::LineStrips3D::new([locus])
                .with_colors([color])
                .with_radii([0.002]),
        )?;
    }
    let mut gaps = (0.0f32, 0.0f32);
    for i in 0..frames {
        let psi = bend(i);
        rec.set_time_sequence("frame", i as i64);
        rec.set_duration_secs("sim_time", i as f64 * scene.def.dt as f64);
        let rod_end = *shape("rod", psi).last().unwrap();
        for (name, color) in spines {
            let points = shape(name, psi);
            rec.log(
                format!("world/spine/{name}"),
                &rerun::LineStrips3D::new([points.iter().map(|p| p.to_array())])
                    .with_colors([color])
                    .with_radii([0.006]),
            )?;
            if name != "rod" {
                let gap = (*points.last().unwrap() - rod_end).length();
                if name == "equal_chain" {
                    gaps.0 = gaps.0.max(gap);
                } else {
                    gaps.1 = gaps.1.max(gap);
                }
                rec.log(
                    format!("metrics/end_gap_cm/{name}"),
                    &rerun::Scalars::single(100.0 * gap as f64),
                )?;
            }
        }
        rec.log("metrics/bend_rad", &rerun::Scalars::single(psi as f64))?;
    }
    rec.flush_blocking()?;
    Ok(gaps)
}

/// Writes a sweep's rows to `path`: the chart itself (the PNG the sweep wrote) in a 2D view,
/// and per method the log10 of the mean dislocation and the time per step against an
/// `iterations` timeline (Rerun's plots have no log axis, and the residual spans four decades).
/// The CSV and the machine go in as a text document.
pub fn save_sweep(
    path: &Path,
    scene: &str,
    rows: &[crate::sweep::SweepRow],
    machine: &str,
    chart_png: &[u8],
) -> anyhow::Result<()> {
    use rerun::blueprint::Spatial2DView;
    create_parent(path)?;
    let plots = Vertical::new([
        ContainerLike::from(
            TimeSeriesView::new("log10 mean dislocation (cm) by iterations")
                .with_origin("sweep/residual_log10"),
        ),
        ContainerLike::from(
            TimeSeriesView::new("Time per step (us) by iterations").with_origin("sweep/step_us"),
        ),
    ]);
    let left = Tabs::new([
        ContainerLike::from(
            Spatial2DView::new("Residual against time per step").with_origin("sweep/chart"),
        ),
        ContainerLike::from(TextDocumentView::new("Sweep CSV").with_origin("sweep/table")),
    ]);
    let blueprint = Blueprint::new(
        Horizontal::new([ContainerLike::from(left), ContainerLike::from(plots)])
            .with_column_shares([0.6, 0.4]),
    )
    .with_auto_views(false);
    let rec = rerun::RecordingStreamBuilder::new(APPLICATION_ID)
        .recording_name(format!("{scene}_sweep"))
        .with_blueprint(blueprint)
        .save(path)?;
    rec.set_log_time_enabled(false);
    rec.log_static(
        "sweep/table",
        &rerun::TextDocument::new(format!(
            "# {scene} sweep\n\nMachine: {machine}\n\n```\n{}```\n",
            crate::sweep::to_csv(rows)
        ))
        .with_media_type(rerun::MediaType::markdown()),
    )?;
    rec.log_static(
        "sweep/chart",
        &rerun::EncodedImage::from_file_contents(chart_png.to_vec()),
    )?;
    let mut methods: Vec<&str> = rows.iter().map(|r| r.method.as_str()).collect();
    methods.dedup();
    for (index, method) in methods.iter().enumerate() {
        let [r, g, b] = crate::chart::PALETTE[index % crate::chart::PALETTE.len()];
        // `rod/exact x4` -> entity `rod/exact_x4` (no spaces in entity paths)
        let entity = method.replace(' ', "_");
        let color = rerun::Color::from_rgb(r, g, b);
        for kind in ["residual_log10", "step_us"] {
            rec.log_static(
                format!("sweep/{kind}/{entity}"),
                &rerun::SeriesLines::new()
                    .with_colors([color])
                    .with_names([*method]),
            )?;
        }
        for row in rows
            .iter()
            .filter(|row| row.method == *method && row.failed.is_none())
        {
            rec.set_time_sequence("iterations", row.iterations as i64);
            if row.mean_dislocation_cm > 0.0 {
                rec.log(
                    format!("sweep/residual_log10/{entity}"),
                    &rerun::Scalars::single(row.mean_dislocation_cm.log10()),
                )?;
            }
            rec.log(
                format!("sweep/step_us/{entity}"),
                &rerun::Scalars::single(row.step_us),
            )?;
        }
    }
    rec.flush_blocking()?;
    Ok(())
}
