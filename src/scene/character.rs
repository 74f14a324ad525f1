//! A `[[character]]` read into what the builder takes: its rig, its clip's pose at the chosen
//! time (with the scene's extra joint turns, placed), and the clip's velocities there, so the
//! physics takes over from the animation in motion (paper §6: the ragdoll starts from whatever
//! the animation hands over).

use super::locate::Seg;
use super::{CharacterDef, Scene, SceneError};
use crate::math::{quat_from_degrees, rotation_vector, Iso, Quat, Vec3};
use crate::ragdoll::character::{region_parts, CharacterSpec};
use crate::ragdoll::RodParams;
use crate::rig::skeleton::AnimationSkeleton;
use crate::rig::{Animation, Rig};

/// The time between the two poses the handover velocities are taken from (s): one keyframe of
/// a 30 Hz clip, centred on the handover time.
pub const HANDOVER_SPAN: f32 = 1.0 / 30.0;

impl Scene {
    /// The rig of `[[character]]` `i`, what to build of it, and with `play_from` the clip's
    /// poses to play before the handover; files are read relative to the scene file.
    pub(super) fn character_spec(
        &self,
        i: usize,
        c: &CharacterDef,
    ) -> Result<(Rig, CharacterSpec, Option<PlayedPoses>), SceneError> {
        let at = |field: &str| {
            [
                Seg::Key("character".into()),
                Seg::Index(i),
                Seg::Key(field.into()),
            ]
        };
        let dir = self.path.parent().unwrap_or(std::path::Path::new("."));
        let rig = Rig::load(dir.join(&c.rig)).map_err(|m| self.error_at(&at("rig"), m))?;
        let clip = match &c.clip {
            Some(clip) => {
                Some(Animation::load(dir.join(clip)).map_err(|m| self.error_at(&at("clip"), m))?)
            }
            None => None,
        };
        let names = [&c.region.from, &c.region.to].into_iter();
        let unknown = |field: &'static str, name: &String| (field, name.clone());
        let missing = (names.map(|n| unknown("region", n)))
            .chain(c.fixed.iter().map(|n| unknown("fixed", n)))
            .chain(c.pose.keys().map(|n| unknown("pose", n)))
            .find(|(_, n)| rig.part_index(n).is_none());
        if let Some((field, name)) = missing {
            let message = format!("the rig {} has no part {name:?}", rig.name);
            return Err(self.error_at(&at(field), message));
        }
        let animation_skeleton = match (&c.skeleton, &c.skeleton_pose) {
            (None, None) => None,
            (Some(_), None) => {
                let message = "a skeleton needs its neutral pose, skeleton_pose".to_string();
                return Err(self.error_at(&at("skeleton"), message));
            }
            (None, Some(_)) => {
                let message = "a neutral pose needs its skeleton, skeleton".to_string();
                return Err(self.error_at(&at("skeleton_pose"), message));
            }
            (Some(skeleton), Some(pose)) => {
                // a region that is no chain of the rig is the spine's mistake, named there
                region_parts(&rig, &c.region.from, &c.region.to)
                    .map_err(|m| self.error_at(&at("spine"), m))?;
                let skeleton = AnimationSkeleton::load(dir.join(skeleton))
                    .and_then(|s| s.spine_chain(&c.region.from, &c.region.to).map(|_| s))
                    .map_err(|m| self.error_at(&at("skeleton"), m))?;
                let neutral_locals = Animation::load(dir.join(pose))
                    .and_then(|pose| skeleton.locals_from(&pose))
                    .map_err(|m| self.error_at(&at("skeleton_pose"), m))?;
                Some((skeleton, neutral_locals))
            }
        };
        let posed_at = |time: f32| posed(&rig, clip.as_ref(), time, c);
        // per frame from `play_from` to the handover, one frame `dt` apart, the last at `time`
        let played = c.play_from.map(|from| {
            let (dt, frames) = (
                self.def.dt,
                ((c.time - from) / self.def.dt).round().max(0.0),
            );
            let frames = frames as usize;
            (0..=frames)
                .map(|k| posed_at(c.time - (frames - k) as f32 * dt))
                .collect()
        });
        let pose = posed_at(c.time);
        let before = posed_at(c.time - HANDOVER_SPAN / 2.0);
        let after = posed_at(c.time + HANDOVER_SPAN / 2.0);
        let velocities = (before.iter().zip(&after))
            .map(|(a, b)| {
                let linear = (b.translation - a.translation) / HANDOVER_SPAN;
                let turn = (b.rotation * a.rotation.inverse()).normalize();
                (linear, rotation_vector(turn) / HANDOVER_SPAN)
            })
            .collect();
        let spec = CharacterSpec {
            name: c.name.clone(),
            pose,
            velocities,
            spine: c.spine,
            region: (c.region.from.clone(), c.region.to.clone()),
            fixed: c.fixed.clone(),
            joint_flavour: c.joint_flavour.unwrap_or(self.def.joint_flavour),
            rod: RodParams {
                alpha_bend: c.alpha_b,
                alpha_twist: c.alpha_t,
                twist_mode: c.twist,
                ..RodParams::default()
            },
            animation_skeleton,
        };
        Ok((rig, spec, played))
    }
}

/// Per frame of a played clip, the rig's parts' world poses.
pub(super) type PlayedPoses = Vec<Vec<Iso>>;

/// The rig's parts' world poses at `time` of `clip` (none: the rig file's pose), each of the
/// character's extra turns applied about the world's axes at its joint (parents first), placed.
fn posed(rig: &Rig, clip: Option<&Animation>, time: f32, c: &CharacterDef) -> Vec<Iso> {
    let mut locals = match clip {
        Some(clip) => rig.local_from_world(&rig.pose(clip, time)),
        None => rig.bind_locals(),
    };
    for part in 0..rig.parts.len() {
        let Some(degrees) = c.pose.get(&rig.parts[part].joint_name) else {
            continue;
        };
        let parent = match rig.parts[part].parent {
            Some(p) => rig.world_from_local(&locals)[p].rotation,
            None => Quat::IDENTITY,
        };
        let turn = parent.inverse() * quat_from_degrees(*degrees) * parent;
        locals[part].rotation = (turn * locals[part].rotation).normalize();
    }
    let place = Iso::new(Vec3::from(c.position), quat_from_degrees(c.rotation));
    (rig.world_from_local(&locals).into_iter())
        .map(|p| place * p)
        .collect()
}
