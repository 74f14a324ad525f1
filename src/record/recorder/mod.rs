//! [`Recorder`]: streams a lab into a recording as it runs.
//!
//! Each frame fills one row of every entity's [`Track`] and every scalar series; every
//! [`FLUSH_WALL_S`] of wall time they are sent as one chunk per entity, after waiting for the
//! block before to be written. What never changes
//! (shapes, colours, radii, series styles) is logged once, static.

mod rods_bones;

use rerun::RecordingStream;

use super::bodies::{
    body_batches, log_colors, log_ground, log_shapes, log_static_poses, pose_track_kind,
    shape_poses, sleep_colors, BodyBatch,
};
use super::columns::ScalarColumns;
use super::file::{self, flush};
use super::style::{fixed_color, spine_color};
use super::tracks::{Track, TrackKind};
use super::{RecordingInfo, FLUSH_WALL_S};
use crate::body::{BodyId, BodyKind};
use crate::constraint::Constraint;
use crate::lab::Lab;
use crate::metrics::FrameMetrics;
use crate::scene::RecordDef;
use crate::sim::Observer;
use crate::world::SimulationError;
use rods_bones::{rod_groups, Bones, RodGroup, ROD_SERIES};

/// The residual series, one instance per ragdoll.
const RESIDUAL_SERIES: [&str; 3] = [
    "metrics/dislocation_cm",
    "metrics/angular_rad",
    "metrics/pose_deviation_cm",
];

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
    /// The rods (constraint indices), in the order of their instances in [`ROD_SERIES`].
    rods: Vec<usize>,
    rod_groups: Vec<RodGroup>,
    /// `metrics/rod`: the [`ROD_SERIES`], an instance per rod each.
    rod_series: usize,
    /// Per bone method, created from the first frame's metrics.
    bones: Bones,
    /// `metrics/energy`: kinetic, potential and total.
    energy: usize,
    /// `metrics/contact_depth_cm`: penetration at the solver's points and overlap found afresh.
    contact_depth: usize,
    /// `metrics/total`: dislocation and angular violation summed over the ragdolls.
    totals: usize,
    contacts: Track,
    /// When the sink was last flushed (wall clock).
    flushed_at: std::time::Instant,
    /// Every scalar series.
    scalars: ScalarColumns,
    /// Send every frame as it comes (a viewer is watching), not a block per second.
    pub live: bool,
}

/// The lines of `metrics/energy`, `metrics/total` and `metrics/contact_depth_cm`.
const ENERGY_SERIES: [&str; 3] = ["kinetic", "potential", "total"];
const TOTAL_SERIES: [&str; 2] = ["dislocation_cm", "angular_rad"];
const CONTACT_DEPTH_SERIES: [&str; 2] =
    ["penetration at the solver's points", "overlap found afresh"];

/// The group a body is drawn in, `world/<group>/...`: every ragdoll's bodies together
/// (`ragdolls`; an instance per body, not an entity per ragdoll, keeps the file's footer small),
/// a plain group of joints and rods under its own name (`loose`), bodies that never move
/// (`fixed`, drawn once), else `props`.
fn group_of(lab: &Lab, body: BodyId) -> String {
    match lab.ragdoll_of(body) {
        Some(r) if r.spine.is_some() => "ragdolls".to_string(),
        Some(r) => r.name.clone(),
        None if lab.world.body(body).kind == BodyKind::Fixed => "fixed".to_string(),
        None => "props".to_string(),
    }
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
        let (fixed, batches): (Vec<_>, Vec<_>) =
            body_batches(lab, |id| format!("world/{}", group_of(lab, id)))
                .into_iter()
                .partition(|b| {
                    b.bodies
                        .iter()
                        .all(|&id| world.body(id).kind == BodyKind::Fixed)
                });
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
        let (rods, rod_groups) = rod_groups(lab);
        let mut scalars = ScalarColumns::default();
        let ragdolls = lab.ragdolls.len();
        let residuals = RESIDUAL_SERIES.map(|path| scalars.series(path, ragdolls));
        let rod_series = scalars.series("metrics/rod", ROD_SERIES.len() * rods.len());
        let energy = scalars.series("metrics/energy", ENERGY_SERIES.len());
        let contact_depth = scalars.series("metrics/contact_depth_cm", CONTACT_DEPTH_SERIES.len());
        let totals = scalars.series("metrics/total", TOTAL_SERIES.len());
        let mut recorder = Recorder {
            rec,
            options: info.options.clone(),
            batches,
            poses,
            joints,
            residuals,
            rods,
            rod_groups,
            rod_series,
            bones: Bones::default(),
            energy,
            contact_depth,
            totals,
            contacts: Track::new("world/contacts", TrackKind::Arrows),
            flushed_at: std::time::Instant::now(),
            scalars,
            live: false,
        };
        recorder.log_static(lab, &info)?;
        for batch in &fixed {
            log_shapes(&recorder.rec, world, batch, vec![fixed_color()])?;
            log_static_poses(&recorder.rec, world, batch)?;
        }
        Ok(recorder)
    }

    /// The recording stream it writes to.
    pub fn stream(&self) -> &RecordingStream {
        &self.rec
    }

    /// After a whole run: its final state hash (`state_hash`, static text), then the file's
    /// end ([`file::finish`]): an error if any of the recording could not be written.
    pub fn finish(&mut self, report: &crate::sim::RunReport) -> anyhow::Result<()> {
        self.rec.log_static(
            "state_hash",
            &rerun::TextDocument::new(format!("{:016x}", report.state_hash)),
        )?;
        self.send()?;
        file::finish(&self.rec)
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
        for group in &mut self.rod_groups {
            group.centerlines.send(rec)?;
            group.frames.send(rec)?;
        }
        for track in self.bones.tracks_mut() {
            track.send(rec)?;
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
                // (a character's kinematic bodies play its clip until they turn dynamic)
                let moves = world.body(id).kind != BodyKind::Fixed;
                match (moves, lab.ragdoll_of(id)) {
                    (false, _) => fixed_color(),
                    (true, None) if !world.body(id).is_dynamic() => fixed_color(),
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
        let names = |names: &[&str]| rerun::SeriesLines::new().with_names(names.to_vec());
        let energy_colors = [(250, 150, 40), (70, 130, 240), (235, 235, 235)]
            .map(|(r, g, b)| rerun::Color::from_rgb(r, g, b));
        if self.options.energy {
            rec.log_static(
                "metrics/energy",
                &names(&ENERGY_SERIES).with_colors(energy_colors),
            )?;
        }
        if world.settings.contacts {
            rec.log_static("metrics/contact_depth_cm", &names(&CONTACT_DEPTH_SERIES))?;
        }
        if lab.ragdolls.len() > 2 {
            rec.log_static("metrics/total", &names(&TOTAL_SERIES))?;
        }
        self.log_rod_styles(world)
    }

    fn log_frame(&mut self, lab: &Lab, metrics: &FrameMetrics) -> anyhow::Result<()> {
        let world = &lab.world;
        if !world.frame.is_multiple_of(self.options.every.max(1) as u64) {
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
                    log_colors(&self.rec, world, batch, colors, (frame, time))?;
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
            let energies = [
                metrics.kinetic_energy,
                metrics.potential_energy,
                metrics.total_energy(),
            ];
            for (instance, energy) in energies.into_iter().enumerate() {
                self.scalars.set(self.energy, instance, energy as f64);
            }
        }
        if world.settings.sleep {
            (self.scalars).push("metrics/awake_bodies", world.awake_bodies as f64);
        }
        if self.live {
            self.send()?; // not flushed: the batcher forwards chunks as they come
        }
        if self.flushed_at.elapsed().as_secs_f64() >= FLUSH_WALL_S {
            // Wait for the last block to be written (or the writer to fail) only now, a
            // second later: the writer encodes a block while the next second is simulated.
            flush(&self.rec)?;
            self.send()?;
            self.flushed_at = std::time::Instant::now();
        }
        Ok(())
    }

    /// Contact points and normals (a scene switch), the deepest penetration at the points and
    /// found afresh, and, with many ragdolls, the residuals summed over all of them.
    fn log_contacts(&mut self, lab: &Lab, metrics: &FrameMetrics, frame: i64) {
        let world = &lab.world;
        let scalars = &mut self.scalars;
        if world.settings.contacts {
            let depth = self.contact_depth;
            scalars.set(depth, 0, metrics.max_penetration_cm as f64);
            scalars.set(depth, 1, metrics.max_overlap_cm as f64);
        }
        if lab.ragdolls.len() > 2 {
            let (dislocation, angular) = metrics.totals();
            scalars.set(self.totals, 0, dislocation as f64);
            scalars.set(self.totals, 1, angular as f64);
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
