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
//! - `metrics/rod/<ragdoll>/<rod>/{psi,tau,length_violation_cm,curve_violation_rad}`;
//! - `metrics/bones/<ragdoll>/<method>/{length_error_cm,chest_gap_cm}`;
//! - `metrics/dislocation_cm/<ragdoll>`, `metrics/angular_rad/<ragdoll>`: residual scalars, one
//!   plot per measure with one series per ragdoll so spines compare in one plot;
//! - `metrics/energy/{kinetic,potential,total}`: energy (J);
//! - `metrics/awake_bodies`: dynamic bodies awake, with sleeping on (sleeping bodies are drawn
//!   in their colour faded toward grey);
//! - `scene`: the scene file (static), `failure`: why a run stopped early, if it did,
//!   `state_hash`: the final state's hash (static text, 16 hex digits) after a whole run.
//!
//! Timelines: `frame` (sequence, 0 = initial state) and `sim_time` (seconds).

use std::path::Path;

use rerun::blueprint::{
    Blueprint, ContainerLike, Horizontal, Spatial3DView, Tabs, TextDocumentView, TimeSeriesView,
    Vertical,
};
use rerun::RecordingStream;

use crate::body::BodyId;
use crate::constraint::Constraint;
use crate::lab::Lab;
use crate::math::{Quat, Vec3};
use crate::metrics::FrameMetrics;
use crate::ragdoll::SpineKind;
use crate::scene::{RecordDef, Scene};
use crate::shape::Shape;
use crate::sim::Observer;
use crate::skeleton::BoneMethod;
use crate::world::{SimulationError, World};

mod columns;
pub mod tune;

use columns::ScalarColumns;

/// Application id of every rodlab recording.
pub const APPLICATION_ID: &str = "rodlab";

/// Flush the sink once this much wall time or simulated time (s) has passed since the last
/// flush, whichever comes first, so a killed run loses at most that much of either.
const FLUSH_EVERY_S: f64 = 1.0;
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

/// Opens a recording of `scene` that writes to `path` (creating its folder), with its blueprint.
pub fn save_to(path: &Path, scene: &Scene) -> anyhow::Result<RecordingStream> {
    create_parent(path)?;
    let rec = rerun::RecordingStreamBuilder::new(APPLICATION_ID)
        .recording_name(scene.name())
        .with_blueprint(blueprint(scene))
        .save(path)?;
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

/// A batch's poses this frame (and its colours, if any changed).
fn log_poses(
    rec: &RecordingStream,
    world: &World,
    batch: &mut BodyBatch,
    colors: Vec<rerun::Color>,
) -> anyhow::Result<()> {
    batch.translations.clear();
    batch.rotations.clear();
    for (&id, &(offset, axis_rotation)) in batch.bodies.iter().zip(&batch.local_offsets) {
        let body = world.body(id);
        batch
            .translations
            .push((body.position + body.orientation * offset).to_array());
        let q = body.orientation * axis_rotation;
        batch
            .rotations
            .push(rerun::Quaternion::from_xyzw(q.to_array()));
    }
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

/// Streams a lab (its world and ragdolls) into a Rerun recording; plugs into [`crate::sim::run`] as its observer.
pub struct Recorder {
    rec: RecordingStream,
    options: RecordDef,
    batches: Vec<BodyBatch>,
    /// Per joint group: entity and constraint indices.
    joint_groups: Vec<(String, Vec<usize>)>,
    anchor_buffer: Vec<[f32; 3]>,
    metric_paths: Vec<(String, String, String)>,
    /// Per rod constraint: (constraint index, world entity prefix, metrics prefix).
    rods: Vec<(usize, String, String)>,
    /// Scratch for arcs and frames.
    points: Vec<[f32; 3]>,
    arrows: Vec<[f32; 3]>,
    arrow_origins: Vec<[f32; 3]>,
    arrow_colors: Vec<rerun::Color>,
    /// When the sink was last flushed: wall clock and simulated time (s).
    flushed_at: (std::time::Instant, f64),
    /// Every scalar series, sent as columns at each flush.
    scalars: ScalarColumns,
}

/// Points sampled along each rod's centerline.
const CENTERLINE_SAMPLES: usize = 24;
/// Material frames drawn along each rod.
const FRAME_SAMPLES: usize = 7;

fn group_of(lab: &Lab, body: BodyId) -> String {
    lab.ragdoll_of(body)
        .map_or_else(|| "props".to_string(), |r| r.name.clone())
}

fn spine_color(spine: SpineKind) -> rerun::Color {
    // Fig. 8 colours: three-joint spine blue, rod red; single joint green.
    match spine {
        SpineKind::Chain3 => rerun::Color::from_rgb(60, 110, 220),
        SpineKind::Rod => rerun::Color::from_rgb(220, 60, 50),
        SpineKind::Single => rerun::Color::from_rgb(60, 170, 90),
    }
}

impl Recorder {
    pub fn new(rec: RecordingStream, lab: &Lab, scene: &Scene) -> anyhow::Result<Self> {
        let world = &lab.world;
        rec.set_log_time_enabled(false);
        let batches = body_batches(lab, |id| format!("world/{}", group_of(lab, id)));
        let mut joint_groups: Vec<(String, Vec<usize>)> = Vec::new();
        for (i, c) in world.constraints.iter().enumerate() {
            if matches!(c, Constraint::BallSocket(_)) {
                let entity = format!("world/{}/joints", group_of(lab, c.bodies().0));
                match joint_groups.iter_mut().find(|(e, _)| *e == entity) {
                    Some((_, list)) => list.push(i),
                    None => joint_groups.push((entity, vec![i])),
                }
            }
        }
        let rods = world
            .constraints
            .iter()
            .enumerate()
            .filter_map(|(i, c)| match c {
                Constraint::Rod(rod) => {
                    let group = group_of(lab, rod.body_a);
                    let short = rod.name.rsplit('/').next().unwrap_or(&rod.name).to_string();
                    Some((
                        i,
                        format!("world/{group}/rod/{short}"),
                        format!("metrics/rod/{group}/{short}"),
                    ))
                }
                _ => None,
            })
            .collect();
        let metric_paths = lab
            .ragdolls
            .iter()
            .map(|r| {
                (
                    format!("metrics/dislocation_cm/{}", r.name),
                    format!("metrics/angular_rad/{}", r.name),
                    format!("metrics/pose_deviation_cm/{}", r.name),
                )
            })
            .collect();
        let mut recorder = Recorder {
            rec,
            options: scene.def.record.clone(),
            batches,
            joint_groups,
            anchor_buffer: Vec::new(),
            metric_paths,
            rods,
            points: Vec::new(),
            arrows: Vec::new(),
            arrow_origins: Vec::new(),
            arrow_colors: Vec::new(),
            flushed_at: (std::time::Instant::now(), 0.0),
            scalars: ScalarColumns::default(),
        };
        recorder.log_static(lab, scene)?;
        Ok(recorder)
    }

    pub fn stream(&self) -> &RecordingStream {
        &self.rec
    }

    /// After a whole run: its final state hash (`state_hash`, static text), then a flush.
    pub fn finish(&mut self, report: &crate::sim::RunReport) -> anyhow::Result<()> {
        self.rec.log_static(
            "state_hash",
            &rerun::TextDocument::new(format!("{:016x}", report.state_hash)),
        )?;
        self.scalars.send(&self.rec)?;
        flush(&self.rec)
    }

    fn log_static(&mut self, lab: &Lab, scene: &Scene) -> anyhow::Result<()> {
        let world = &lab.world;
        let rec = &self.rec;
        rec.log_static("world", &rerun::ViewCoordinates::RIGHT_HAND_Y_UP())?;
        let text = format!(
            "# {}\n\n`{}`\n\n```toml\n{}\n```\n",
            scene.name(),
            scene.path.display(),
            scene.text
        );
        rec.log_static("scene", &rerun::TextDocument::from_markdown(text))?;
        // Half-spaces: a 10 m square slab under each plane.
        for body in world
            .bodies
            .iter()
            .filter(|b| matches!(b.shape, Shape::HalfSpace))
        {
            let normal = body.orientation * Vec3::Y;
            rec.log_static(
                format!("world/static/{}", body.name),
                &rerun::Boxes3D::from_centers_and_half_sizes(
                    [(body.position - 0.01 * normal).to_array()],
                    [[5.0, 0.01, 5.0]],
                )
                .with_quaternions([rerun::Quaternion::from_xyzw(body.orientation.to_array())])
                .with_colors([rerun::Color::from_rgb(150, 150, 140)])
                .with_fill_mode(rerun::components::FillMode::Solid),
            )?;
        }
        // Ground grid reference: a thin floor outline at y = 0.
        rec.log_static(
            "world/floor",
            &rerun::Boxes3D::from_centers_and_half_sizes([[0.0, -0.005, 0.0]], [[3.0, 0.005, 3.0]])
                .with_colors([rerun::Color::from_rgb(120, 120, 120)]),
        )?;
        for batch in &mut self.batches {
            let color_of = |id: BodyId| {
                let body = world.body(id);
                match (body.is_dynamic(), lab.ragdoll_of(id)) {
                    (false, _) => rerun::Color::from_rgb(110, 110, 110),
                    (true, Some(r)) => spine_color(r.spine),
                    (true, None) => rerun::Color::from_rgb(200, 160, 60),
                }
            };
            let mut colors: Vec<_> = batch.bodies.iter().map(|&id| color_of(id)).collect();
            if world.settings.sleep {
                // per frame instead: static data would shadow the sleep colours
                batch.colors = std::mem::take(&mut colors);
            }
            log_shapes(rec, world, batch, colors)?;
        }
        for (r, paths) in lab.ragdolls.iter().zip(&self.metric_paths) {
            let style = rerun::SeriesLines::new()
                .with_colors([spine_color(r.spine)])
                .with_names([r.name.as_str()]);
            for path in [&paths.0, &paths.1, &paths.2] {
                rec.log_static(path.as_str(), &style)?;
            }
        }
        Ok(())
    }

    fn log_frame(&mut self, lab: &Lab, metrics: &FrameMetrics) -> anyhow::Result<()> {
        let world = &lab.world;
        if world.frame % self.options.every.max(1) as u64 != 0 {
            return Ok(()); // `[record] every = N`: frames 0, N, 2N, ...
        }
        let rec = &self.rec;
        rec.set_time_sequence("frame", world.frame as i64);
        rec.set_duration_secs("sim_time", world.time);
        self.scalars.at(world.frame as i64, world.time);
        if self.options.bodies {
            for batch in &mut self.batches {
                let colors = sleep_colors(batch, world);
                log_poses(rec, world, batch, colors)?;
            }
        }
        if self.options.joints {
            for (entity, constraints) in &self.joint_groups {
                self.anchor_buffer.clear();
                for &i in constraints {
                    if let Constraint::BallSocket(joint) = &world.constraints[i] {
                        let (a, b) =
                            joint.world_anchors(world.body(joint.body_a), world.body(joint.body_b));
                        self.anchor_buffer.push(a.to_array());
                        self.anchor_buffer.push(b.to_array());
                    }
                }
                rec.log(
                    entity.as_str(),
                    &rerun::Points3D::new(self.anchor_buffer.iter().copied())
                        .with_radii([0.012])
                        .with_colors([rerun::Color::from_rgb(250, 200, 40)]),
                )?;
            }
        }
        if self.options.residuals {
            for ((dislocation, angular, deviation), residual) in
                self.metric_paths.iter().zip(&metrics.ragdolls)
            {
                self.scalars
                    .push(deviation.as_str(), residual.pose_deviation_cm as f64);
                self.scalars
                    .push(dislocation.as_str(), residual.dislocation_cm as f64);
                self.scalars
                    .push(angular.as_str(), residual.angular_rad as f64);
            }
        }
        if self.options.rods {
            self.log_rods(world, metrics)?;
        }
        self.log_contacts(lab, metrics)?;
        if self.options.bones {
            self.log_bones(lab, metrics)?;
        }
        if self.options.energy {
            self.scalars
                .push("metrics/energy/kinetic", metrics.kinetic_energy as f64);
            self.scalars
                .push("metrics/energy/potential", metrics.potential_energy as f64);
            self.scalars
                .push("metrics/energy/total", metrics.total_energy() as f64);
        }
        if world.settings.sleep {
            self.scalars
                .push("metrics/awake_bodies", world.awake_bodies as f64);
        }
        let (wall, simulated) = self.flushed_at;
        if wall.elapsed().as_secs_f64() >= FLUSH_EVERY_S || world.time - simulated >= FLUSH_EVERY_S
        {
            self.scalars.send(&self.rec)?;
            flush(&self.rec)?;
            self.flushed_at = (std::time::Instant::now(), world.time);
        }
        Ok(())
    }
}

impl Recorder {
    /// Per rod: centerline (LineStrips3D), material frames (Arrows3D), and its scalars.
    fn log_rods(&mut self, world: &World, metrics: &FrameMetrics) -> anyhow::Result<()> {
        for ((index, entity, metric), state) in self.rods.iter().zip(&metrics.rods) {
            let Constraint::Rod(rod) = &world.constraints[*index] else {
                continue;
            };
            let (a, b) = (world.body(rod.body_a), world.body(rod.body_b));
            self.points.clear();
            for i in 0..CENTERLINE_SAMPLES {
                let s = i as f32 / (CENTERLINE_SAMPLES - 1) as f32;
                self.points.push(rod.sample(a, b, s).0.to_array());
            }
            self.rec.log(
                format!("{entity}/centerline"),
                &rerun::LineStrips3D::new([self.points.iter().copied()])
                    .with_radii([0.008])
                    .with_colors([rerun::Color::from_rgb(250, 140, 40)]),
            )?;
            self.arrows.clear();
            self.arrow_origins.clear();
            self.arrow_colors.clear();
            for i in 0..FRAME_SAMPLES {
                let s = i as f32 / (FRAME_SAMPLES - 1) as f32;
                let (point, frame) = rod.sample(a, b, s);
                for (axis, color) in [
                    (Vec3::Y, rerun::Color::from_rgb(230, 60, 60)),
                    (Vec3::Z, rerun::Color::from_rgb(60, 200, 90)),
                ] {
                    self.arrow_origins.push(point.to_array());
                    self.arrows.push((0.06 * (frame * axis)).to_array());
                    self.arrow_colors.push(color);
                }
            }
            self.rec.log(
                format!("{entity}/frames"),
                &rerun::Arrows3D::from_vectors(self.arrows.iter().copied())
                    .with_origins(self.arrow_origins.iter().copied())
                    .with_colors(self.arrow_colors.iter().copied()),
            )?;
            for (name, value) in [
                ("psi", state.psi),
                ("tau", state.tau),
                ("length_violation_cm", 100.0 * state.length_error),
                ("curve_violation_rad", state.curve_error),
            ] {
                self.scalars.push(&format!("{metric}/{name}"), value as f64);
            }
        }
        Ok(())
    }

    /// Contact points and normals (a scene switch), the deepest penetration at the points and
    /// found afresh, and, with many ragdolls, the residuals summed over all of them.
    fn log_contacts(&mut self, lab: &Lab, metrics: &FrameMetrics) -> anyhow::Result<()> {
        let world = &lab.world;
        if world.settings.contacts {
            self.scalars
                .push("metrics/penetration_cm", metrics.max_penetration_cm as f64);
            self.scalars
                .push("metrics/overlap_cm", metrics.max_overlap_cm as f64);
        }
        if lab.ragdolls.len() > 2 {
            let (dislocation, angular) = metrics.totals();
            self.scalars
                .push("metrics/total/dislocation_cm", dislocation as f64);
            self.scalars
                .push("metrics/total/angular_rad", angular as f64);
        }
        if !self.options.contacts {
            return Ok(());
        }
        self.points.clear();
        self.arrows.clear();
        for p in &world.contacts.points {
            self.points
                .push(world.body(p.body_b).world_point(p.local_b).to_array());
            self.arrows.push((0.05 * p.normal).to_array());
        }
        self.rec.log(
            "world/contacts",
            &rerun::Arrows3D::from_vectors(self.arrows.iter().copied())
                .with_origins(self.points.iter().copied())
                .with_colors([rerun::Color::from_rgb(255, 80, 200)]),
        )?;
        Ok(())
    }

    /// Animation bones per ragdoll and mapping method, with their errors.
    fn log_bones(&mut self, lab: &Lab, metrics: &FrameMetrics) -> anyhow::Result<()> {
        for &(ragdoll_index, method, error) in &metrics.bones {
            let ragdoll = &lab.ragdolls[ragdoll_index];
            let Some(skeleton) = &ragdoll.skeleton else {
                continue;
            };
            let bones = skeleton.pose(&lab.world, method);
            self.rec.log(
                format!("world/{}/bones/{}", ragdoll.name, method.name()),
                &rerun::LineStrips3D::new([bones.origins.iter().map(|p| p.to_array())])
                    .with_radii([0.006])
                    .with_colors([bone_color(method)]),
            )?;
            let metric = format!("metrics/bones/{}/{}", ragdoll.name, method.name());
            self.scalars
                .push(&format!("{metric}/length_error_cm"), error.length_cm as f64);
            self.scalars
                .push(&format!("{metric}/chest_gap_cm"), error.chest_gap_cm as f64);
        }
        Ok(())
    }
}

fn bone_color(method: BoneMethod) -> rerun::Color {
    match method {
        BoneMethod::Rigid => rerun::Color::from_rgb(240, 240, 240),
        BoneMethod::Orientation => rerun::Color::from_rgb(250, 220, 60),
        BoneMethod::OrientationPosition => rerun::Color::from_rgb(60, 220, 250),
        BoneMethod::Arc => rerun::Color::from_rgb(250, 90, 200),
    }
}

impl Observer for Recorder {
    fn begin(&mut self, lab: &Lab, metrics: &FrameMetrics) -> anyhow::Result<()> {
        self.log_frame(lab, metrics)
    }

    fn frame(&mut self, lab: &Lab, metrics: &FrameMetrics) -> anyhow::Result<()> {
        self.log_frame(lab, metrics)
    }

    fn failed(&mut self, lab: &Lab, error: &SimulationError) {
        self.rec.set_time_sequence("frame", lab.world.frame as i64);
        let text = format!("# Run stopped\n\n{error}\n");
        let _ = self
            .rec
            .log("failure", &rerun::TextDocument::from_markdown(text));
        let _ = self.scalars.send(&self.rec);
        let _ = flush(&self.rec);
    }
}

impl Drop for Recorder {
    fn drop(&mut self) {
        let _ = self.scalars.send(&self.rec);
        let _ = flush(&self.rec);
    }
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
