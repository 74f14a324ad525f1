//! Skeletal animations (Jolt's `SkeletalAnimation`) and posing a rig from them.
//!
//! An animation gives, per joint, keyframes of the joint's local transform: its rotation and
//! translation relative to its parent joint (the root's relative to the world). Sampling
//! follows `SkeletalAnimation::Sample`: a looping animation wraps the time by its duration
//! (the last key time of its first joint); before a joint's first key the first key holds,
//! after its last the last; between two keys the translation is interpolated linearly and the
//! rotation by spherical interpolation along the shorter arc. World transforms follow
//! `SkeletonPose::CalculateJointMatrices`, `world = parent's world * local`, and as
//! `Ragdoll::SetPose` does, a part's body pose is its joint's world transform.

use super::tof::{Document, View};
use super::{ConstraintSpace, Part, Rig, SwingTwist};
use crate::math::{quat_slerp, Iso, Quat, Vec3};
use std::path::Path;

/// One key of a joint.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Keyframe {
    /// Time of the key (s).
    pub time: f32,
    /// Translation relative to the parent joint, in its frame (m).
    pub translation: Vec3,
    /// Rotation relative to the parent joint (unit).
    pub rotation: Quat,
}

/// The keys of one joint.
#[derive(Clone, Debug, PartialEq)]
pub struct AnimatedJoint {
    /// The skeleton joint's name.
    pub name: String,
    /// Keys in time order (at least one).
    pub keys: Vec<Keyframe>,
}

/// A skeletal animation.
#[derive(Clone, Debug, PartialEq)]
pub struct Animation {
    /// The file's stem, e.g. `walk`.
    pub name: String,
    /// Whether sampling wraps the time by the duration (Jolt's default when the file does not
    /// say) or holds the last key.
    pub looping: bool,
    /// The animated joints.
    pub joints: Vec<AnimatedJoint>,
}

impl Animation {
    /// Reads an animation from a `.tof` file.
    pub fn load(path: impl AsRef<Path>) -> Result<Animation, String> {
        let (text, file) = super::read(path.as_ref())?;
        Animation::from_str(&text, &file)
    }

    /// Reads an animation from the text of a `.tof` file called `file`.
    pub fn from_str(text: &str, file: &str) -> Result<Animation, String> {
        let doc = Document::parse(text, file)?;
        let root = doc.root()?;
        if root.obj.type_name != "SkeletalAnimation" {
            return Err(format!(
                "{file}:{}: {}: expected SkeletalAnimation",
                root.obj.line, root.obj.label
            ));
        }
        let looping = super::optional(&root, "mIsLooping", true, View::boolean)?;
        let mut joints = Vec::new();
        for j in root.inlines("mAnimatedJoints")? {
            let mut keys: Vec<Keyframe> = Vec::new();
            for k in j.inlines("mKeyframes")? {
                let time = k.float("mTime")?;
                if keys.last().is_some_and(|last| !(time >= last.time)) {
                    return Err(k.error("mTime", "key times go back"));
                }
                keys.push(Keyframe {
                    time,
                    translation: k.vec3("mTranslation")?,
                    rotation: k.quat("mRotation")?,
                });
            }
            if keys.is_empty() {
                return Err(j.error("mKeyframes", "a joint has no keys"));
            }
            joints.push(AnimatedJoint {
                name: j.string("mJointName")?.to_string(),
                keys,
            });
        }
        Ok(Animation {
            name: super::stem(file),
            looping,
            joints,
        })
    }

    /// The duration (s): the last key time of the first joint, as Jolt has it.
    pub fn duration(&self) -> f32 {
        self.joints
            .first()
            .and_then(|j| j.keys.last())
            .map_or(0.0, |k| k.time)
    }

    /// Each animated joint's local transform at `time` (s): name, translation, rotation.
    pub fn sample<'a>(&'a self, time: f32) -> Vec<(&'a str, Vec3, Quat)> {
        let duration = self.duration();
        let time = if self.looping && duration > 0.0 {
            time.rem_euclid(duration)
        } else {
            time
        };
        let sample = |keys: &[Keyframe]| {
            // The first key at or after `time`; the one before it is the last key before.
            let high = keys.partition_point(|k| k.time < time);
            match (high, keys.get(high)) {
                (0, _) => (keys[0].translation, keys[0].rotation),
                (_, None) => (keys[high - 1].translation, keys[high - 1].rotation),
                (_, Some(k2)) => {
                    let k1 = keys[high - 1];
                    let s = (time - k1.time) / (k2.time - k1.time);
                    let rotation = quat_slerp(k1.rotation, k2.rotation, s).normalize();
                    (k1.translation.lerp(k2.translation, s), rotation)
                }
            }
        };
        let joints = self.joints.iter().filter(|j| !j.keys.is_empty());
        let pose = |j: &'a AnimatedJoint| {
            let (translation, rotation) = sample(&j.keys);
            (j.name.as_str(), translation, rotation)
        };
        joints.map(pose).collect()
    }
}

impl Part {
    /// The body's pose in the rig file: its joint's world transform there.
    pub fn pose(&self) -> Iso {
        Iso::new(self.position, self.rotation)
    }
}

/// A constraint frame in a body's frame: anchor, twist axis, plane axis.
pub type BodyFrame = (Vec3, Vec3, Vec3);

impl SwingTwist {
    /// The two constraint frames in their bodies' frames (origin at the part's position, not
    /// its centre of mass), for any pose of the parts.
    pub fn body_frames(&self, rig: &Rig) -> [BodyFrame; 2] {
        let frame = |body: usize, p: Vec3, twist: Vec3, plane: Vec3| {
            let part = &rig.parts[body];
            let inv = part.pose().inverse();
            match self.space {
                ConstraintSpace::LocalToBodyCom => (part.mass.com + p, twist, plane),
                ConstraintSpace::World => (
                    inv.transform_point(p),
                    inv.rotation * twist,
                    inv.rotation * plane,
                ),
            }
        };
        let (s, b1, b2) = (self, self.body1, self.body2);
        [
            frame(b1, s.position1, s.twist_axis1, s.plane_axis1),
            frame(b2, s.position2, s.twist_axis2, s.plane_axis2),
        ]
    }

    /// The two anchors in world space with the parts at `poses` (in part order).
    pub fn world_anchors(&self, rig: &Rig, poses: &[Iso]) -> [Vec3; 2] {
        let [(p1, ..), (p2, ..)] = self.body_frames(rig);
        [
            poses[self.body1].transform_point(p1),
            poses[self.body2].transform_point(p2),
        ]
    }
}

impl Rig {
    /// The parts' poses in the rig file.
    pub fn bind_pose(&self) -> Vec<Iso> {
        self.parts.iter().map(Part::pose).collect()
    }

    /// The parts' local transforms in the rig's pose: each part's pose relative to its
    /// parent's, the root's as its world pose.
    pub fn bind_locals(&self) -> Vec<Iso> {
        self.local_from_world(&self.bind_pose())
    }

    /// World poses from local transforms, in part order: `world = parent's world * local`.
    pub fn world_from_local(&self, locals: &[Iso]) -> Vec<Iso> {
        let mut world: Vec<Iso> = Vec::with_capacity(self.parts.len());
        for (part, &local) in self.parts.iter().zip(locals) {
            world.push(match part.parent {
                Some(p) if p < world.len() => world[p] * local,
                _ => local,
            });
        }
        world
    }

    /// Local transforms from world poses, in part order: `local = parent's world⁻¹ * world`.
    pub fn local_from_world(&self, world: &[Iso]) -> Vec<Iso> {
        let parent = |p: Option<usize>| p.and_then(|p| world.get(p));
        let local =
            |(part, w): (&Part, &Iso)| parent(part.parent).map_or(*w, |pw| pw.inverse() * *w);
        self.parts.iter().zip(world).map(local).collect()
    }

    /// The parts' world poses at `time` of `animation`, in part order. A part whose joint the
    /// animation does not move keeps its local transform from the rig's pose; animated joints
    /// the rig does not have are ignored.
    pub fn pose(&self, animation: &Animation, time: f32) -> Vec<Iso> {
        let mut locals = self.bind_locals();
        for (name, translation, rotation) in animation.sample(time) {
            if let Some(i) = self.part_index(name) {
                locals[i] = Iso::new(translation, rotation);
            }
        }
        self.world_from_local(&locals)
    }
}
