//! Rods and bones in the recording: the rods' centerlines and material frames with their
//! scalars (`metrics/rod/*`), the animation bones per mapping method with their errors
//! (`metrics/bones/*`), and a game character's whole animation skeleton
//! (`world/<character>/skeleton`).
//!
//! Every rod of a group is one instance of the group's two entities, and every ragdoll's bones
//! one strip of its method's entity: the file's footer keeps a manifest row per chunk, one chunk
//! per entity per second, so entities per ragdoll made a run's memory grow with its length.

use std::collections::HashMap;

use super::{group_of, Recorder};
use crate::constraint::Constraint;
use crate::lab::Lab;
use crate::math::Vec3;
use crate::metrics::FrameMetrics;
use crate::record::style::{bone_color, strip_style};
use crate::record::tracks::{Track, TrackKind};
use crate::skeleton::BoneMethod;
use crate::world::World;

/// Points sampled along each rod's centerline: 7 segments keep a 90-degree arc within 0.7%
/// of its radius (under a millimetre for the spine) of the true curve.
const CENTERLINE_SAMPLES: usize = 8;
/// Material frames drawn along each rod: both ends and the middle (the twist is linear in s).
const FRAME_SAMPLES: usize = 3;
/// Length of the drawn material frame axes (m).
const FRAME_AXIS_LENGTH: f32 = 0.06;

/// The rods of one group: `world/<group>/rods/centerlines` (a strip per rod) and
/// `world/<group>/rods/frames` (six arrows per rod).
pub(super) struct RodGroup {
    /// The group's rods, as positions in [`Recorder::rods`], in instance order.
    members: Vec<usize>,
    pub(super) centerlines: Track,
    pub(super) frames: Track,
}

/// The rod scalars, all in `metrics/rod`: an instance per rod for each, named `<rod> <scalar>`.
pub(super) const ROD_SERIES: [&str; 4] =
    ["psi", "tau", "length_violation_cm", "curve_violation_rad"];

/// The bone errors, all in `metrics/bones`: an instance per (ragdoll, method) for each.
const BONE_SERIES: [&str; 2] = ["length_error_cm", "chest_gap_cm"];

/// Where each (ragdoll, method)'s bones and errors go, set from the first frame's metrics.
#[derive(Default)]
pub(super) struct Bones {
    started: bool,
    /// The bones posed by one mapping method, a strip per ragdoll:
    /// `world/<group>/bones/<method>`.
    pub(super) tracks: Vec<Track>,
    /// (ragdoll, method) -> (its track in `tracks`, its instance in the error series).
    slots: HashMap<(usize, &'static str), (usize, usize)>,
    /// `metrics/bones`'s id, and its instances per error (the (ragdoll, method) pairs).
    series: usize,
    pairs: usize,
    /// Per character with an animation skeleton: its ragdoll, the method its spine is drawn
    /// by, and `world/<character>/skeleton`, a two-point strip per bone.
    skeletons: Vec<(usize, BoneMethod, Track)>,
    /// The skeleton's world poses, reused frame to frame.
    poses: Vec<crate::math::Iso>,
}

impl Bones {
    /// Every track, for sending.
    pub(super) fn tracks_mut(&mut self) -> impl Iterator<Item = &mut Track> {
        let skeletons = self.skeletons.iter_mut().map(|(_, _, t)| t);
        self.tracks.iter_mut().chain(skeletons)
    }
}

/// The lab's rods (constraint indices; instance i of [`ROD_SERIES`]), and their drawings by group.
pub(super) fn rod_groups(lab: &Lab) -> (Vec<usize>, Vec<RodGroup>) {
    let rods: Vec<usize> = (lab.world.constraints.iter().enumerate())
        .filter(|(_, c)| matches!(c, Constraint::Rod(_)))
        .map(|(i, _)| i)
        .collect();
    let mut groups: Vec<RodGroup> = Vec::new();
    for (position, &i) in rods.iter().enumerate() {
        let entity = format!(
            "world/{}/rods",
            group_of(lab, lab.world.constraints[i].bodies().0)
        );
        let centerlines = format!("{entity}/centerlines");
        match groups
            .iter_mut()
            .find(|g| g.centerlines.entity() == centerlines)
        {
            Some(group) => group.members.push(position),
            None => groups.push(RodGroup {
                members: vec![position],
                centerlines: Track::new(centerlines, TrackKind::Strips),
                frames: Track::new(format!("{entity}/frames"), TrackKind::Arrows),
            }),
        }
    }
    (rods, groups)
}

impl Recorder {
    /// The rods' static styles (centerline colour, width and labels, frame colours) and their
    /// series' names: one line per rod, named after it.
    pub(super) fn log_rod_styles(&self, world: &World) -> anyhow::Result<()> {
        let rec = &self.rec;
        let name = |position: usize| world.constraints[self.rods[position]].name().to_string();
        for group in &self.rod_groups {
            let orange = rerun::Color::from_rgb(250, 140, 40);
            let labels = group.members.iter().map(|&m| name(m));
            rec.log_static(
                group.centerlines.entity(),
                &strip_style(0.008, orange)
                    .with_labels(labels)
                    .with_show_labels(false),
            )?;
            // Normal red, binormal green, at each sample of each rod.
            let (red, green) = (
                rerun::Color::from_rgb(230, 60, 60),
                rerun::Color::from_rgb(60, 200, 90),
            );
            let arrows = group.members.len() * FRAME_SAMPLES;
            let colors = (0..arrows).flat_map(|_| [red, green]);
            rec.log_static(
                group.frames.entity(),
                &rerun::Arrows3D::update_fields().with_colors(colors),
            )?;
        }
        let names = (ROD_SERIES.iter())
            .flat_map(|series| (0..self.rods.len()).map(move |m| (m, series)))
            .map(|(m, series)| format!("{} {series}", name(m)));
        if !self.rods.is_empty() {
            rec.log_static("metrics/rod", &rerun::SeriesLines::new().with_names(names))?;
        }
        Ok(())
    }

    /// Every rod's centerline, material frames, and scalars.
    pub(super) fn log_rods(&mut self, world: &World, metrics: &FrameMetrics, frame: i64) {
        for group in &mut self.rod_groups {
            group.centerlines.begin(frame, world.time);
            group.frames.begin(frame, world.time);
            for &member in &group.members {
                let Constraint::Rod(rod) = &world.constraints[self.rods[member]] else {
                    continue;
                };
                let (a, b) = (world.body(rod.body_a), world.body(rod.body_b));
                group
                    .centerlines
                    .push_strip((0..CENTERLINE_SAMPLES).map(|i| {
                        let s = i as f32 / (CENTERLINE_SAMPLES - 1) as f32;
                        rod.sample(a, b, s).0.to_array()
                    }));
                for i in 0..FRAME_SAMPLES {
                    let s = i as f32 / (FRAME_SAMPLES - 1) as f32;
                    let (point, material_frame) = rod.sample(a, b, s);
                    for axis in [Vec3::Y, Vec3::Z] {
                        let vector = FRAME_AXIS_LENGTH * (material_frame * axis);
                        (group.frames).push_arrow(point.to_array(), vector.to_array());
                    }
                }
            }
        }
        for (instance, state) in metrics.rods.iter().enumerate() {
            let values = [
                state.psi,
                state.tau,
                100.0 * state.length_error,
                state.curve_error,
            ];
            for (k, value) in values.into_iter().enumerate() {
                let line = k * self.rods.len() + instance;
                self.scalars.set(self.rod_series, line, value as f64);
            }
        }
    }

    /// The animation bones, a strip per ragdoll in its method's entity, with their errors.
    pub(super) fn log_bones(
        &mut self,
        lab: &Lab,
        metrics: &FrameMetrics,
        frame: i64,
    ) -> anyhow::Result<()> {
        if !self.bones.started {
            self.start_bones(lab, metrics)?;
            self.bones.started = true;
        }
        for track in self.bones.tracks_mut() {
            track.begin(frame, lab.world.time);
        }
        let Bones {
            skeletons, poses, ..
        } = &mut self.bones;
        for (ragdoll, method, track) in skeletons.iter_mut() {
            let Some(skeleton) = &lab.ragdolls[*ragdoll].hd_skeleton else {
                continue;
            };
            skeleton.pose_into(&lab.world, *method, poses);
            for (joint, parent) in skeleton.parents().iter().enumerate() {
                if let Some(parent) = parent {
                    let ends = [poses[*parent].translation, poses[joint].translation];
                    track.push_strip(ends.map(|p| p.to_array()));
                }
            }
        }
        for &(ragdoll_index, method, error) in &metrics.bones {
            let ragdoll = &lab.ragdolls[ragdoll_index];
            let (Some(skeleton), Some(&(track, instance))) = (
                &ragdoll.skeleton,
                self.bones.slots.get(&(ragdoll_index, method.name())),
            ) else {
                continue;
            };
            let origins = &skeleton.pose(&lab.world, method).origins;
            let track = &mut self.bones.tracks[track];
            track.push_strip(origins.iter().map(|p| p.to_array()));
            let (series, pairs) = (self.bones.series, self.bones.pairs);
            let scalars = &mut self.scalars;
            scalars.set(series, instance, error.length_cm as f64);
            scalars.set(series, pairs + instance, error.chest_gap_cm as f64);
        }
        Ok(())
    }

    /// The bone tracks and error series for the (ragdoll, method) pairs of the first frame: an
    /// entity per (group, method), an error instance per pair, named `<ragdoll> <method>`.
    fn start_bones(&mut self, lab: &Lab, metrics: &FrameMetrics) -> anyhow::Result<()> {
        let mut styles: Vec<(BoneMethod, Vec<String>)> = Vec::new();
        let mut names = Vec::new();
        for &(ragdoll, method, _) in &metrics.bones {
            let r = &lab.ragdolls[ragdoll];
            if r.skeleton.is_none() {
                continue;
            }
            let group = group_of(lab, crate::body::BodyId(r.bodies.start as u32));
            let entity = format!("world/{group}/bones/{}", method.name());
            let tracks = &mut self.bones.tracks;
            let track = match tracks.iter().position(|t| t.entity() == entity) {
                Some(t) => t,
                None => {
                    tracks.push(Track::new(entity, TrackKind::Strips));
                    styles.push((method, Vec::new()));
                    tracks.len() - 1
                }
            };
            styles[track].1.push(r.name.clone());
            let slot = (track, names.len());
            self.bones.slots.insert((ragdoll, method.name()), slot);
            names.push(format!("{} {}", r.name, method.name()));
        }
        for (track, (method, labels)) in self.bones.tracks.iter().zip(styles) {
            let style = strip_style(0.006, bone_color(method))
                .with_labels(labels)
                .with_show_labels(false);
            self.rec.log_static(track.entity(), &style)?;
        }
        for (i, r) in lab.ragdolls.iter().enumerate() {
            let Some(skeleton) = &r.hd_skeleton else {
                continue;
            };
            // the rod's bones by the paper's interpolation that meets the chest, so the drawn
            // skeleton is whole
            let methods = skeleton.spine().methods();
            let method = match methods.contains(&BoneMethod::OrientationPosition) {
                true => BoneMethod::OrientationPosition,
                false => methods[0],
            };
            let entity = format!("world/{}/skeleton", r.name);
            let style = strip_style(0.004, rerun::Color::from_rgb(235, 235, 235));
            self.rec.log_static(entity.as_str(), &style)?;
            let track = Track::new(entity, TrackKind::Strips);
            self.bones.skeletons.push((i, method, track));
        }
        self.bones.pairs = names.len();
        self.bones.series = (self.scalars).series("metrics/bones", BONE_SERIES.len() * names.len());
        let lines = (BONE_SERIES.iter())
            .flat_map(|series| names.iter().map(move |n| format!("{n} {series}")));
        if !names.is_empty() {
            let style = rerun::SeriesLines::new().with_names(lines);
            self.rec.log_static("metrics/bones", &style)?;
        }
        Ok(())
    }
}
