//! Bodies drawn in batches: one archetype per group and shape kind (`<group>/capsules`,
//! `.../spheres`, `.../boxes`), shapes and labels static, poses per frame; with sleeping on,
//! the colours follow each body's sleep state.

use rerun::RecordingStream;

use super::tracks::TrackKind;
use crate::body::BodyId;
use crate::lab::Lab;
use crate::math::{Quat, Vec3};
use crate::shape::Shape;
use crate::world::World;

/// Which bodies one batched entity draws, and how.
pub(super) struct BodyBatch {
    pub(super) entity: String,
    pub(super) bodies: Vec<BodyId>,
    /// Capsules: body-space offset of the first cap centre and rotation taking +Z to the axis.
    pub(super) local_offsets: Vec<(Vec3, Quat)>,
    /// With sleeping on, the awake colours, and the sleep state last logged (colours are then
    /// logged per frame when a body's state changes, instead of once as static data).
    pub(super) colors: Vec<rerun::Color>,
    pub(super) logged_asleep: Vec<bool>,
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
pub(super) fn sleep_colors(
    batch: &mut BodyBatch,
    world: &crate::world::World,
) -> Vec<rerun::Color> {
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
pub(super) fn body_batches(lab: &Lab, group: impl Fn(BodyId) -> String) -> Vec<BodyBatch> {
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
                crate::math::quat_from_rotation_arc(Vec3::Z, axis.unit()),
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
                colors: Vec::new(),
                logged_asleep: Vec::new(),
            }),
        }
    }
    batches
}

/// A batch's shapes, labelled with the bodies' short names, and its colours (none: per
/// frame), as static data.
pub(super) fn log_shapes(
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
pub(super) fn shape_poses<'a>(
    world: &'a World,
    batch: &'a BodyBatch,
) -> impl Iterator<Item = ([f32; 3], [f32; 4])> + 'a {
    (batch.bodies.iter().zip(&batch.local_offsets)).map(|(&id, &(offset, axis_rotation))| {
        let body = world.body(id);
        let centre = body.position + body.orientation * offset;
        (
            centre.to_array(),
            (body.orientation * axis_rotation).to_array(),
        )
    })
}

/// The kind of track a batch's poses go to.
pub(super) fn pose_track_kind(world: &World, batch: &BodyBatch) -> TrackKind {
    match world.body(batch.bodies[0]).shape {
        Shape::Capsule { .. } => TrackKind::Capsules,
        Shape::Sphere { .. } => TrackKind::Ellipsoids,
        Shape::Cuboid { .. } | Shape::HalfSpace => TrackKind::Boxes,
    }
}

/// A batch's colours from frame `frame` (simulated `time`, s) on: one chunk per change, sent as
/// columns rather than `log`ged, so the file's chunks do not depend on when Rerun's batcher
/// flushes (`rerun rrd compare` then finds two runs of a sleeping scene equal).
pub(super) fn log_colors(
    rec: &RecordingStream,
    world: &World,
    batch: &BodyBatch,
    colors: Vec<rerun::Color>,
    (frame, time): (i64, f64),
) -> anyhow::Result<()> {
    let entity = batch.entity.as_str();
    let times = [
        rerun::TimeColumn::new_sequence("frame", [frame]),
        rerun::TimeColumn::new_duration_secs("sim_time", [time]),
    ];
    let lengths = [colors.len()];
    let columns: Vec<_> = match pose_track_kind(world, batch) {
        TrackKind::Capsules => (rerun::Capsules3D::update_fields().with_colors(colors))
            .columns(lengths)?
            .collect(),
        TrackKind::Ellipsoids => (rerun::Ellipsoids3D::update_fields().with_colors(colors))
            .columns(lengths)?
            .collect(),
        _ => (rerun::Boxes3D::update_fields().with_colors(colors))
            .columns(lengths)?
            .collect(),
    };
    rec.send_columns(entity, times, columns)?;
    Ok(())
}

/// The half-spaces (a 10 m square slab under each plane) and a floor outline at y = 0, static.
pub(super) fn log_ground(rec: &RecordingStream, world: &World) -> anyhow::Result<()> {
    // Half-spaces: a 10 m square slab under each plane.
    for body in (world.bodies.iter()).filter(|b| matches!(b.shape, Shape::HalfSpace)) {
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
    Ok(())
}

/// The poses of a batch that never moves, once, as static data.
pub(super) fn log_static_poses(
    rec: &RecordingStream,
    world: &World,
    batch: &BodyBatch,
) -> anyhow::Result<()> {
    let (centres, rotations): (Vec<[f32; 3]>, Vec<rerun::Quaternion>) = shape_poses(world, batch)
        .map(|(centre, q)| (centre, rerun::Quaternion::from_xyzw(q)))
        .unzip();
    let entity = batch.entity.as_str();
    match pose_track_kind(world, batch) {
        TrackKind::Capsules => rec.log_static(
            entity,
            &rerun::Capsules3D::update_fields()
                .with_translations(centres)
                .with_quaternions(rotations),
        )?,
        TrackKind::Ellipsoids => rec.log_static(
            entity,
            &rerun::Ellipsoids3D::update_fields()
                .with_centers(centres)
                .with_quaternions(rotations),
        )?,
        _ => rec.log_static(
            entity,
            &rerun::Boxes3D::update_fields()
                .with_centers(centres)
                .with_quaternions(rotations),
        )?,
    }
    Ok(())
}
