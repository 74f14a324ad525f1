//! [`Recorder`]: streams a lab into a recording as it runs.
//!
//! Each frame fills one row of every entity's [`Track`] and every scalar series; every
//! [`FLUSH_EVERY_S`] of simulated time (or [`FLUSH_WALL_S`] of wall time) they are sent as one
//! chunk per entity, after waiting for the block before to be written. What never changes
//! (shapes, colours, radii, series styles) is logged once, static.

use std::collections::HashMap;

use rerun::RecordingStream;

use super::bodies::{
    body_batches, log_colors, log_ground, log_shapes, pose_track_kind, shape_poses, sleep_colors,
    BodyBatch,
};
use super::columns::ScalarColumns;
use super::style::{bone_color, spine_color, strip_style};
use super::tracks::{Track, TrackKind};
use super::{flush, RecordingInfo, FLUSH_EVERY_S, FLUSH_WALL_S};
use crate::body::BodyId;
use crate::constraint::Constraint;
use crate::lab::Lab;
use crate::math::Vec3;
use crate::metrics::FrameMetrics;
use crate::scene::RecordDef;
use crate::sim::Observer;
use crate::skeleton::BoneMethod;
use crate::world::{SimulationError, World};

/// Points sampled along each rod's centerline: 7 segments keep a 90-degree arc within 0.7%
/// of its radius (under a millimetre for the spine) of the true curve.
const CENTERLINE_SAMPLES: usize = 8;
/// Material frames drawn along each rod: both ends and the middle (the twist is linear in s).
const FRAME_SAMPLES: usize = 3;
/// The residual series, one instance per ragdoll.
const RESIDUAL_SERIES: [&str; 3] = [
    "metrics/dislocation_cm",
    "metrics/angular_rad",
    "metrics/pose_deviation_cm",
];
/// Length of the drawn material frame axes (m).
const FRAME_AXIS_LENGTH: f32 = 0.06;

/// One rod's drawing; its scalars are instance `index` of [`ROD_SERIES`].
struct RodTracks {
    constraint: usize,
    centerline: Track,
    frames: Track,
}

/// The rod scalars, `metrics/rod/<name>`, one instance per rod.
const ROD_SERIES: [&str; 4] = ["psi", "tau", "length_violation_cm", "curve_violation_rad"];

/// One ragdoll's bones by one mapping method, and where their two errors go: the series
/// `metrics/bones/<method>/{length_error_cm,chest_gap_cm}` and the ragdoll's instance in them.
struct BoneTrack {
    track: Track,
    length_error: usize,
    chest_gap: usize,
    instance: usize,
}

/// Streams a lab (its world and ragdolls) into a Rerun recording; plugs into
/// [`crate::sim::run`] as its observer.
pub struct Recorder {
    rec: RecordingStream,
    options: RecordDef,
    batches: Vec<BodyBatch>,
    /// One pose track per batch.
    poses: Vec<Track>,
    /// Per joint group: its anchors' track and constraint indices.
    joints: Vec<(Track, Vec<usize>)>,
    /// Dislocation, angular violation and pose deviation: one instance per ragdoll.
    residuals: [usize; 3],
    rods: Vec<RodTracks>,
    /// [`ROD_SERIES`]: one instance per rod.
    rod_series: [usize; 4],
    /// Per (ragdoll, bone method), created from the first frame's metrics.
    bones: HashMap<(usize, &'static str), BoneTrack>,
    contacts: Track,
    /// When the sink was last flushed: wall clock and simulated time (s).
    flushed_at: (std::time::Instant, f64),
    /// Every scalar series.
    scalars: ScalarColumns,
    /// Send every frame as it comes (a viewer is watching), not a block per second.
    pub live: bool,
}

fn group_of(lab: &Lab, body: BodyId) -> String {
    lab.ragdoll_of(body)
        .map_or_else(|| "props".to_string(), |r| r.name.clone())
}

impl Recorder {
    /// A recorder of `lab` into `rec`; logs the static parts (scene text, ground, shapes, styles)
    /// at once.
    pub fn new(
        rec: RecordingStream,
        lab: &Lab,
        info: impl Into<RecordingInfo>,
    ) -> anyhow::Result<Self> {
        let info = info.into();
        let world = &lab.world;
        rec.set_log_time_enabled(false);
        let batches = body_batches(lab, |id| format!("world/{}", group_of(lab, id)));
        let poses = (batches.iter())
            .map(|b| Track::new(b.entity.clone(), pose_track_kind(world, b)))
            .collect();
        let mut joints: Vec<(Track, Vec<usize>)> = Vec::new();
        for (i, c) in world.constraints.iter().enumerate() {
            if matches!(c, Constraint::BallSocket(_)) {
                let entity = format!("world/{}/joints", group_of(lab, c.bodies().0));
                match joints.iter_mut().find(|(t, _)| t.entity() == entity) {
                    Some((_, list)) => list.push(i),
                    None => joints.push((Track::new(entity, TrackKind::Points), vec![i])),
                }
            }
        }
        let rods: Vec<RodTracks> = (world.constraints.iter().enumerate())
            .filter_map(|(i, c)| match c {
                Constraint::Rod(rod) => {
                    let group = group_of(lab, rod.body_a);
                    let short = rod.name.rsplit('/').next().unwrap_or(&rod.name);
                    let entity = format!("world/{group}/rod/{short}");
                    Some(RodTracks {
                        constraint: i,
                        centerline: Track::new(format!("{entity}/centerline"), TrackKind::Strip),
                        frames: Track::new(format!("{entity}/frames"), TrackKind::Arrows),
                    })
                }
                _ => None,
            })
            .collect();
        let mut scalars = ScalarColumns::default();
        let ragdolls = lab.ragdolls.len();
        let residuals = RESIDUAL_SERIES.map(|path| scalars.series(path, ragdolls));
        let rod_series =
            ROD_SERIES.map(|name| scalars.series(&format!("metrics/rod/{name}"), rods.len()));
        let mut recorder = Recorder {
            rec,
            options: info.options.clone(),
            batches,
            poses,
            joints,
            residuals,
            rods,
            rod_series,
            bones: HashMap::new(),
            contacts: Track::new("world/contacts", TrackKind::Arrows),
            flushed_at: (std::time::Instant::now(), 0.0),
            scalars,
            live: false,
        };
        recorder.log_static(lab, &info)?;
        Ok(recorder)
    }

    /// The recording stream it writes to.
    pub fn stream(&self) -> &RecordingStream {
        &self.rec
    }

    /// After a whole run: its final state hash (`state_hash`, static text), then a flush.
    pub fn finish(&mut self, report: &crate::sim::RunReport) -> anyhow::Result<()> {
        self.rec.log_static(
            "state_hash",
            &rerun::TextDocument::new(format!("{:016x}", report.state_hash)),
        )?;
        self.send()?;
        flush(&self.rec)
    }

    /// Sends every buffered track and scalar series, one chunk each.
    fn send(&mut self) -> anyhow::Result<()> {
        let rec = &self.rec;
        for track in self
            .poses
            .iter_mut()
            .chain(self.joints.iter_mut().map(|(t, _)| t))
        {
            track.send(rec)?;
        }
        for rod in &mut self.rods {
            rod.centerline.send(rec)?;
            rod.frames.send(rec)?;
        }
        for bones in self.bones.values_mut() {
            bones.track.send(rec)?;
        }
        self.contacts.send(rec)?;
        self.scalars.send(rec)
    }

    fn log_static(&mut self, lab: &Lab, info: &RecordingInfo) -> anyhow::Result<()> {
        let world = &lab.world;
        let rec = &self.rec;
        rec.log_static("world", &rerun::ViewCoordinates::RIGHT_HAND_Y_UP())?;
        let text = format!("# {}\n\n{}", info.name, info.about);
        rec.log_static("scene", &rerun::TextDocument::from_markdown(text))?;
        log_ground(rec, world)?;
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
        for (track, _) in &self.joints {
            rec.log_static(
                track.entity(),
                &rerun::Points3D::update_fields()
                    .with_radii([0.012])
                    .with_colors([rerun::Color::from_rgb(250, 200, 40)]),
            )?;
        }
        for rod in &self.rods {
            let orange = rerun::Color::from_rgb(250, 140, 40);
            rec.log_static(rod.centerline.entity(), &strip_style(0.008, orange))?;
            // Normal red, binormal green, at each sample.
            let (red, green) = (
                rerun::Color::from_rgb(230, 60, 60),
                rerun::Color::from_rgb(60, 200, 90),
            );
            let colors = (0..FRAME_SAMPLES).flat_map(|_| [red, green]);
            rec.log_static(
                rod.frames.entity(),
                &rerun::Arrows3D::update_fields().with_colors(colors),
            )?;
        }
        if self.options.contacts {
            rec.log_static(
                self.contacts.entity(),
                &rerun::Arrows3D::update_fields()
                    .with_colors([rerun::Color::from_rgb(255, 80, 200)]),
            )?;
        }
        // One line per ragdoll, named after it, in its spine's colour.
        let style = rerun::SeriesLines::new()
            .with_colors(lab.ragdolls.iter().map(|r| spine_color(r.spine)))
            .with_names(lab.ragdolls.iter().map(|r| r.name.as_str()));
        for path in RESIDUAL_SERIES {
            rec.log_static(path, &style)?;
        }
        // One line per rod, named after its ragdoll (and itself, if the ragdoll has several).
        let rod_names: Vec<String> = (self.rods.iter())
            .map(|r| world.constraints[r.constraint].name().to_string())
            .collect();
        for name in ROD_SERIES {
            let names = rod_names.iter().map(|n| format!("{n} {name}"));
            let style = rerun::SeriesLines::new().with_names(names);
            rec.log_static(format!("metrics/rod/{name}"), &style)?;
        }
        Ok(())
    }

    fn log_frame(&mut self, lab: &Lab, metrics: &FrameMetrics) -> anyhow::Result<()> {
        let world = &lab.world;
        if world.frame % self.options.every.max(1) as u64 != 0 {
            return Ok(()); // `[record] every = N`: frames 0, N, 2N, ...
        }
        let (frame, time) = (world.frame as i64, world.time);
        self.rec.set_time_sequence("frame", frame); // for what is logged at once
        self.rec.set_duration_secs("sim_time", time);
        self.scalars.at(frame, time);
        if self.options.bodies {
            for (batch, track) in self.batches.iter_mut().zip(&mut self.poses) {
                track.begin(frame, time);
                for (centre, rotation) in shape_poses(world, batch) {
                    track.push_pose(centre, rotation);
                }
                let colors = sleep_colors(batch, world);
                if !colors.is_empty() {
                    log_colors(&self.rec, world, batch, colors)?;
                }
            }
        }
        if self.options.joints {
            for (track, constraints) in &mut self.joints {
                track.begin(frame, time);
                for &i in constraints.iter() {
                    if let Constraint::BallSocket(joint) = &world.constraints[i] {
                        let (a, b) =
                            joint.world_anchors(world.body(joint.body_a), world.body(joint.body_b));
                        track.push_point(a.to_array());
                        track.push_point(b.to_array());
                    }
                }
            }
        }
        if self.options.residuals {
            for (i, residual) in metrics.ragdolls.iter().enumerate() {
                let [dislocation, angular, deviation] = self.residuals;
                let scalars = &mut self.scalars;
                scalars.set(dislocation, i, residual.dislocation_cm as f64);
                scalars.set(angular, i, residual.angular_rad as f64);
                scalars.set(deviation, i, residual.pose_deviation_cm as f64);
            }
        }
        if self.options.rods {
            self.log_rods(world, metrics, frame);
        }
        self.log_contacts(lab, metrics, frame);
        if self.options.bones {
            self.log_bones(lab, metrics, frame)?;
        }
        if self.options.energy {
            let scalars = &mut self.scalars;
            scalars.push("metrics/energy/kinetic", metrics.kinetic_energy as f64);
            scalars.push("metrics/energy/potential", metrics.potential_energy as f64);
            scalars.push("metrics/energy/total", metrics.total_energy() as f64);
        }
        if world.settings.sleep {
            (self.scalars).push("metrics/awake_bodies", world.awake_bodies as f64);
        }
        if self.live {
            self.send()?; // not flushed: the batcher forwards chunks as they come
        }
        let (wall, simulated) = self.flushed_at;
        if world.time - simulated >= FLUSH_EVERY_S || wall.elapsed().as_secs_f64() >= FLUSH_WALL_S {
            // Wait for the last block to be written (or the writer to fail) only now, a
            // second later: the writer encodes a block while the next second is simulated.
            flush(&self.rec)?;
            self.send()?;
            self.flushed_at = (std::time::Instant::now(), world.time);
        }
        Ok(())
    }

    /// Per rod: centerline, material frames, and its scalars.
    fn log_rods(&mut self, world: &World, metrics: &FrameMetrics, frame: i64) {
        for (instance, (tracks, state)) in self.rods.iter_mut().zip(&metrics.rods).enumerate() {
            let Constraint::Rod(rod) = &world.constraints[tracks.constraint] else {
                continue;
            };
            let (a, b) = (world.body(rod.body_a), world.body(rod.body_b));
            tracks.centerline.begin(frame, world.time);
            for i in 0..CENTERLINE_SAMPLES {
                let s = i as f32 / (CENTERLINE_SAMPLES - 1) as f32;
                tracks
                    .centerline
                    .push_point(rod.sample(a, b, s).0.to_array());
            }
            tracks.frames.begin(frame, world.time);
            for i in 0..FRAME_SAMPLES {
                let s = i as f32 / (FRAME_SAMPLES - 1) as f32;
                let (point, material_frame) = rod.sample(a, b, s);
                for axis in [Vec3::Y, Vec3::Z] {
                    let vector = FRAME_AXIS_LENGTH * (material_frame * axis);
                    tracks
                        .frames
                        .push_arrow(point.to_array(), vector.to_array());
                }
            }
            let values = [
                state.psi,
                state.tau,
                100.0 * state.length_error,
                state.curve_error,
            ];
            for (&series, value) in self.rod_series.iter().zip(values) {
                self.scalars.set(series, instance, value as f64);
            }
        }
    }

    /// Contact points and normals (a scene switch), the deepest penetration at the points and
    /// found afresh, and, with many ragdolls, the residuals summed over all of them.
    fn log_contacts(&mut self, lab: &Lab, metrics: &FrameMetrics, frame: i64) {
        let world = &lab.world;
        let scalars = &mut self.scalars;
        if world.settings.contacts {
            scalars.push("metrics/penetration_cm", metrics.max_penetration_cm as f64);
            scalars.push("metrics/overlap_cm", metrics.max_overlap_cm as f64);
        }
        if lab.ragdolls.len() > 2 {
            let (dislocation, angular) = metrics.totals();
            scalars.push("metrics/total/dislocation_cm", dislocation as f64);
            scalars.push("metrics/total/angular_rad", angular as f64);
        }
        if !self.options.contacts {
            return;
        }
        self.contacts.begin(frame, world.time);
        for p in &world.contacts.points {
            let point = world.body(p.body_b).world_point(p.local_b);
            (self.contacts).push_arrow(point.to_array(), (0.05 * p.normal).to_array());
        }
    }

    /// Animation bones per ragdoll and mapping method, with their errors.
    fn log_bones(&mut self, lab: &Lab, metrics: &FrameMetrics, frame: i64) -> anyhow::Result<()> {
        if self.bones.is_empty() {
            self.start_bones(lab, metrics)?;
        }
        for &(ragdoll_index, method, error) in &metrics.bones {
            let ragdoll = &lab.ragdolls[ragdoll_index];
            let (Some(skeleton), Some(bones)) = (
                &ragdoll.skeleton,
                self.bones.get_mut(&(ragdoll_index, method.name())),
            ) else {
                continue;
            };
            bones.track.begin(frame, lab.world.time);
            for p in &skeleton.pose(&lab.world, method).origins {
                bones.track.push_point(p.to_array());
            }
            let scalars = &mut self.scalars;
            scalars.set(bones.length_error, bones.instance, error.length_cm as f64);
            scalars.set(bones.chest_gap, bones.instance, error.chest_gap_cm as f64);
        }
        Ok(())
    }

    /// The bone tracks and error series for the (ragdoll, method) pairs of the first frame:
    /// per method, one instance per ragdoll posed by it.
    fn start_bones(&mut self, lab: &Lab, metrics: &FrameMetrics) -> anyhow::Result<()> {
        let mut methods: Vec<(BoneMethod, Vec<usize>)> = Vec::new();
        for &(ragdoll, method, _) in &metrics.bones {
            match methods.iter_mut().find(|(m, _)| *m == method) {
                Some((_, ragdolls)) => ragdolls.push(ragdoll),
                None => methods.push((method, vec![ragdoll])),
            }
        }
        for (method, ragdolls) in methods {
            let series = |scalars: &mut ScalarColumns, name: &str| {
                scalars.series(
                    &format!("metrics/bones/{}/{name}", method.name()),
                    ragdolls.len(),
                )
            };
            let length_error = series(&mut self.scalars, "length_error_cm");
            let chest_gap = series(&mut self.scalars, "chest_gap_cm");
            for name in ["length_error_cm", "chest_gap_cm"] {
                let names = ragdolls.iter().map(|&r| lab.ragdolls[r].name.as_str());
                self.rec.log_static(
                    format!("metrics/bones/{}/{name}", method.name()),
                    &rerun::SeriesLines::new().with_names(names.map(|n| format!("{n} {name}"))),
                )?;
            }
            for (instance, &ragdoll) in ragdolls.iter().enumerate() {
                let entity = format!(
                    "world/{}/bones/{}",
                    lab.ragdolls[ragdoll].name,
                    method.name()
                );
                (self.rec).log_static(entity.as_str(), &strip_style(0.006, bone_color(method)))?;
                let track = Track::new(entity, TrackKind::Strip);
                let bones = BoneTrack {
                    track,
                    length_error,
                    chest_gap,
                    instance,
                };
                self.bones.insert((ragdoll, method.name()), bones);
            }
        }
        Ok(())
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
        let _ = (self.rec).log("failure", &rerun::TextDocument::from_markdown(text));
        let _ = self.send();
        let _ = flush(&self.rec);
    }
}

impl Drop for Recorder {
    fn drop(&mut self) {
        let _ = self.send();
        let _ = flush(&self.rec);
    }
}
