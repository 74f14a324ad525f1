//! Rods and bones in the recording: each rod's centerline and material frames and its scalars
//! (`metrics/rod/*`), and the animation bones per ragdoll and mapping method with their errors
//! (`metrics/bones/*`).

use super::{group_of, Recorder};
use crate::constraint::Constraint;
use crate::lab::Lab;
use crate::math::Vec3;
use crate::metrics::FrameMetrics;
use crate::record::columns::ScalarColumns;
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

/// One rod's drawing; its scalars are instance `index` of [`ROD_SERIES`].
pub(super) struct RodTracks {
    pub(super) constraint: usize,
    pub(super) centerline: Track,
    pub(super) frames: Track,
}

/// The rod scalars, `metrics/rod/<name>`, one instance per rod.
pub(super) const ROD_SERIES: [&str; 4] =
    ["psi", "tau", "length_violation_cm", "curve_violation_rad"];

/// One ragdoll's bones by one mapping method, and where their two errors go: the series
/// `metrics/bones/<method>/{length_error_cm,chest_gap_cm}` and the ragdoll's instance in them.
pub(super) struct BoneTrack {
    pub(super) track: Track,
    pub(super) length_error: usize,
    pub(super) chest_gap: usize,
    pub(super) instance: usize,
}

/// One drawing per rod of the lab, under its group: `world/<group>/rod/<rod>/{centerline,frames}`.
pub(super) fn rod_tracks(lab: &Lab) -> Vec<RodTracks> {
    (lab.world.constraints.iter().enumerate())
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
        .collect()
}

impl Recorder {
    /// The rods' static styles (centerline colour and width, frame colours) and their series'
    /// names: one line per rod, named after its ragdoll (and itself, if the ragdoll has several).
    pub(super) fn log_rod_styles(&self, world: &World) -> anyhow::Result<()> {
        let rec = &self.rec;
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

    /// Per rod: centerline, material frames, and its scalars.
    pub(super) fn log_rods(&mut self, world: &World, metrics: &FrameMetrics, frame: i64) {
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

    /// Animation bones per ragdoll and mapping method, with their errors.
    pub(super) fn log_bones(
        &mut self,
        lab: &Lab,
        metrics: &FrameMetrics,
        frame: i64,
    ) -> anyhow::Result<()> {
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
