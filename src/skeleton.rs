//! The animation skeleton posed back from the simplified physics (paper §6).
//!
//! Animation rigs have four joints between hips and upper spine: bones `pelvis`, `spine_0` ..
//! `spine_3`, `chest`, with origins evenly spaced from 1.060 m to 1.270 m in the reference pose
//! (`shared/humanoid.md`). At the transition (when the ragdoll is built) every bone is attached
//! to a physics body: [`Skeleton::attach`] places the humanoid's bones at their reference
//! heights on their nearest bodies; [`Skeleton::new`] takes any chain's bones as their world
//! poses at the transition and the bodies they follow (a game character's animation skeleton,
//! [`crate::rig::skeleton`]). Every frame the bones are posed back:
//!
//! - [`BoneMethod::Rigid`]: a bone follows its body one to one (chain3 and single spines, and the
//!   pelvis and chest bones always);
//! - [`BoneMethod::Orientation`] (§6, rod): the rotation changes of pelvis and chest since the
//!   transition are interpolated along the chain (slerp by the bone's place `s`), and the bones are
//!   chained from the pelvis with their lengths kept; the chain's end may miss the chest;
//! - [`BoneMethod::OrientationPosition`] (§6, rod): the same, plus the chest-end gap shared out
//!   linearly along the chain, so the end meets the chest and bone lengths change;
//! - [`BoneMethod::Arc`] (beyond the paper, rod): each bone rides the arc, placed at
//!   `gamma(s)` with the material frame `F(s)` and its offset from the straight rod at the
//!   transition.
//!
//! Errors per method: the summed change of bone lengths and the gap between the chest bone's
//! origin and where the chest body puts it, both in cm.

use crate::body::BodyId;
use crate::constraint::Constraint;
use crate::math::{Iso, Quat, Vec3};
use crate::world::World;

/// The animation bones of the spine region, pelvis to chest.
pub const BONE_NAMES: [&str; BONES] = [
    "pelvis", "spine_0", "spine_1", "spine_2", "spine_3", "chest",
];
/// Number of animation bones in the spine region.
pub const BONES: usize = 6;

/// Reference-pose bone origins (y, m).
pub fn reference_heights() -> [f32; BONES] {
    std::array::from_fn(|i| 1.060 + (1.270 - 1.060) * i as f32 / (BONES - 1) as f32)
}

/// How the bones are posed back from the physics (see the module docs).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum BoneMethod {
    /// Each bone follows its body one to one.
    Rigid,
    /// §6: the rotation changes of pelvis and chest interpolated along the chain, lengths kept.
    Orientation,
    /// §6: as `Orientation`, plus the chest-end gap shared out along the chain.
    OrientationPosition,
    /// Each bone rides the rod's arc (beyond the paper).
    Arc,
}

impl BoneMethod {
    /// Lower-case name, as in the metrics series and recordings.
    pub fn name(self) -> &'static str {
        match self {
            BoneMethod::Rigid => "rigid",
            BoneMethod::Orientation => "orientation",
            BoneMethod::OrientationPosition => "orientation_position",
            BoneMethod::Arc => "arc",
        }
    }
}

/// World bone poses.
#[derive(Clone, Copy, Debug, Default)]
pub struct Bones {
    /// World origin of each bone (m), pelvis first.
    pub origins: [Vec3; BONES],
    /// World rotation of each bone.
    pub rotations: [Quat; BONES],
}

/// How far posed-back bones are from the physics.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct BoneError {
    /// Sum over bones of | |o_k+1 - o_k| - L_k | (cm).
    pub length_cm: f32,
    /// Distance from the chest bone's origin to the chest body's placement of it (cm).
    pub chest_gap_cm: f32,
}

/// The animation skeleton of one ragdoll, attached to its physics bodies at the transition.
#[derive(Clone, Debug)]
pub struct Skeleton {
    /// Body each bone follows rigidly, and the bone's pose in that body's frame.
    attached: [(BodyId, Iso); BONES],
    /// Bone lengths at the transition.
    lengths: [f32; BONES - 1],
    /// Transition poses of the bones and of the two end bodies (rod methods).
    bones_at_transition: Bones,
    pelvis: (BodyId, Quat),
    chest: (BodyId, Quat),
    /// Rod spine: constraint index, and per bone its arc parameter and pose in the rod frame.
    rod: Option<(usize, [(f32, Iso); BONES])>,
}

impl Skeleton {
    /// Attaches the bones at the ragdoll's current (transition) pose. `bodies` lists the spine
    /// bodies, pelvis first and chest last, with their centre heights in the reference pose
    /// (where bodies and bones are axis-aligned). `rod` is the index of the rod constraint.
    pub fn attach(world: &World, bodies: &[(BodyId, f32)], rod: Option<usize>) -> Skeleton {
        let heights = reference_heights();
        let nearest = |i: usize, h: f32| -> (BodyId, Iso) {
            // pelvis and chest bones follow their namesakes; the others the nearest body
            let pick = match i {
                0 => &bodies[0],
                i if i == BONES - 1 => bodies.last().unwrap(),
                _ => bodies
                    .iter()
                    .min_by(|a, b| (a.1 - h).abs().total_cmp(&(b.1 - h).abs()))
                    .unwrap(),
            };
            let (id, body_height) = *pick;
            (
                id,
                Iso::new(Vec3::new(0.0, h - body_height, 0.0), Quat::IDENTITY),
            )
        };
        let attached: [(BodyId, Iso); BONES] = std::array::from_fn(|i| nearest(i, heights[i]));
        Skeleton::from_body_frames(world, attached, rod).expect("the humanoid's spine rod")
    }

    /// Attaches the bones at the ragdoll's current (transition) pose, each given by its world
    /// pose there and the body it follows, pelvis first and chest last: the pelvis and chest
    /// bones' bodies are the spine's two ends, whose turns the rod methods share out. `rod` is
    /// the index of the rod constraint joining them; an error when it is not a rod.
    pub fn new(
        world: &World,
        bones: &[(BodyId, Iso); BONES],
        rod: Option<usize>,
    ) -> Result<Skeleton, String> {
        let attached = bones.map(|(id, pose)| {
            let body = world.body(id);
            (
                id,
                Iso::new(body.position, body.orientation).inverse() * pose,
            )
        });
        Skeleton::from_body_frames(world, attached, rod)
    }

    /// Attaches the bones given by their poses in their bodies' frames (see [`Skeleton::new`]).
    fn from_body_frames(
        world: &World,
        attached: [(BodyId, Iso); BONES],
        rod: Option<usize>,
    ) -> Result<Skeleton, String> {
        let (pelvis, chest) = (attached[0].0, attached[BONES - 1].0);
        let mut skeleton = Skeleton {
            attached,
            lengths: [0.0; BONES - 1],
            bones_at_transition: Bones::default(),
            pelvis: (pelvis, world.body(pelvis).orientation),
            chest: (chest, world.body(chest).orientation),
            rod: None,
        };
        let bones = skeleton.rigid(world);
        skeleton.lengths =
            std::array::from_fn(|k| (bones.origins[k + 1] - bones.origins[k]).length());
        skeleton.bones_at_transition = bones;
        if let Some(index) = rod {
            let Some(Constraint::Rod(r)) = world.constraints.get(index) else {
                return Err(format!("constraint {index} is not a rod"));
            };
            let (a, b) = (world.body(r.body_a), world.body(r.body_b));
            let (start, frame) = r.sample(a, b, 0.0);
            let tangent = frame * Vec3::X;
            let placement = std::array::from_fn(|k| {
                let s = (bones.origins[k] - start).dot(tangent) / r.rest_length;
                let on_rod = start + s * r.rest_length * tangent;
                let local = Iso::new(
                    frame.inverse() * (bones.origins[k] - on_rod),
                    frame.inverse() * bones.rotations[k],
                );
                (s, local)
            });
            skeleton.rod = Some((index, placement));
        }
        Ok(skeleton)
    }

    /// The body each bone follows, pelvis first.
    pub fn bodies(&self) -> [BodyId; BONES] {
        self.attached.map(|(id, _)| id)
    }

    /// The mapping methods that apply: the three rod methods for a rod spine, else `Rigid`.
    pub fn methods(&self) -> &'static [BoneMethod] {
        if self.rod.is_some() {
            &[
                BoneMethod::Orientation,
                BoneMethod::OrientationPosition,
                BoneMethod::Arc,
            ]
        } else {
            &[BoneMethod::Rigid]
        }
    }

    /// World bone poses by `method`.
    pub fn pose(&self, world: &World, method: BoneMethod) -> Bones {
        match method {
            BoneMethod::Rigid => self.rigid(world),
            BoneMethod::Orientation => self.interpolated(world, false),
            BoneMethod::OrientationPosition => self.interpolated(world, true),
            BoneMethod::Arc => self.arc(world),
        }
    }

    /// The bone length error and chest-end gap of `bones`.
    pub fn error(&self, world: &World, bones: &Bones) -> BoneError {
        let length: f32 = (0..BONES - 1)
            .map(|k| ((bones.origins[k + 1] - bones.origins[k]).length() - self.lengths[k]).abs())
            .sum();
        let chest_target = self.placed_by_body(world, BONES - 1).translation;
        BoneError {
            length_cm: 100.0 * length,
            chest_gap_cm: 100.0 * (bones.origins[BONES - 1] - chest_target).length(),
        }
    }

    fn placed_by_body(&self, world: &World, k: usize) -> Iso {
        let (id, local) = self.attached[k];
        let body = world.body(id);
        Iso::new(body.position, body.orientation) * local
    }

    fn rigid(&self, world: &World) -> Bones {
        let mut bones = Bones::default();
        for k in 0..BONES {
            let pose = self.placed_by_body(world, k);
            bones.origins[k] = pose.translation;
            bones.rotations[k] = pose.rotation;
        }
        bones
    }

    /// §6: share the rotation change of pelvis and chest out along the chain.
    fn interpolated(&self, world: &World, share_position: bool) -> Bones {
        let change = |(id, at_transition): (BodyId, Quat)| {
            (world.body(id).orientation * at_transition.inverse()).normalize()
        };
        let (pelvis_change, chest_change) = (change(self.pelvis), change(self.chest));
        let t = &self.bones_at_transition;
        let mut bones = Bones::default();
        bones.origins[0] = self.placed_by_body(world, 0).translation;
        for k in 0..BONES {
            let s = k as f32 / (BONES - 1) as f32;
            let rotation_change = crate::math::quat_slerp(pelvis_change, chest_change, s);
            bones.rotations[k] = (rotation_change * t.rotations[k]).normalize();
            if k + 1 < BONES {
                bones.origins[k + 1] =
                    bones.origins[k] + rotation_change * (t.origins[k + 1] - t.origins[k]);
            }
        }
        if share_position {
            let gap = self.placed_by_body(world, BONES - 1).translation - bones.origins[BONES - 1];
            for k in 0..BONES {
                bones.origins[k] += gap * (k as f32 / (BONES - 1) as f32);
            }
        }
        bones
    }

    /// Beyond the paper: bones ride the arc gamma(s) with the material frame F(s).
    fn arc(&self, world: &World) -> Bones {
        let Some((index, placement)) = &self.rod else {
            return self.rigid(world);
        };
        let Constraint::Rod(rod) = &world.constraints[*index] else {
            return self.rigid(world);
        };
        let (a, b) = (world.body(rod.body_a), world.body(rod.body_b));
        let mut bones = Bones::default();
        for (k, (s, local)) in placement.iter().enumerate() {
            let (point, frame) = rod.sample(a, b, *s);
            bones.origins[k] = point + frame * local.translation;
            bones.rotations[k] = (frame * local.rotation).normalize();
        }
        bones
    }
}
