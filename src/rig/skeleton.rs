//! A game's animation skeleton (Jolt's `Skeleton`) posed back from a character's bodies
//! (paper §6), in the spirit of Jolt's `SkeletonMapper`.
//!
//! The animation skeleton has more joints than the ragdoll has parts (the Human's has 71: the
//! ragdoll's 23 plus a root under the hips, a fifth spine joint, fingers, props and toes).
//! Its neutral pose is a clip with one key per joint, each joint's local transform.
//!
//! At the handover ([`AnimationSkeleton::handover_poses`]) a joint named like a rig part takes
//! that part's world pose; any other joint takes its parent's world pose times its neutral
//! local transform. A joint with neither a part nor a parent (the root) keeps its neutral
//! offset from the first joint below it that has a part, so it moves with the character.
//!
//! Each frame ([`MappedSkeleton::pose`]), in joint order (parents first):
//! - the region's chain of [`BONES`] joints (the spine, hips to chest) is posed by the chosen
//!   [`BoneMethod`] through a [`Skeleton`], each bone following its own part's body or, when
//!   the spine removed that part or the rig has none, the body of the chain's joint nearest
//!   to it along the chain, the lower on a tie (the rig's `C_Spine_sjnt_2` part spans the
//!   animation skeleton's `C_Spine_sjnt_3`);
//! - any other joint with a body follows it rigidly, its offset from the body kept from the
//!   handover (so does the root, following the body of the joint it is anchored to);
//! - every other joint is its parent's world pose times its local transform at the handover.

use super::tof::Document;
use super::{Animation, Rig};
use crate::body::BodyId;
use crate::math::Iso;
use crate::skeleton::{BoneMethod, Skeleton, BONES};
use crate::world::World;
use std::path::Path;

#[cfg(test)]
#[path = "skeleton_tests.rs"]
mod tests;

/// One joint of an animation skeleton.
#[derive(Clone, Debug, PartialEq)]
pub struct SkeletonJoint {
    /// The joint's name, unique in its skeleton.
    pub name: String,
    /// The parent joint's index, always lower than the joint's own; `None` for a root.
    pub parent: Option<usize>,
}

/// An animation skeleton read from Jolt's `Skeleton` text stream: joints, parents first.
#[derive(Clone, Debug, PartialEq)]
pub struct AnimationSkeleton {
    /// The file's stem, e.g. `skeleton_hd`.
    pub name: String,
    /// The joints, each after its parent.
    pub joints: Vec<SkeletonJoint>,
}

impl AnimationSkeleton {
    /// Reads a skeleton from a `.tof` file.
    pub fn load(path: impl AsRef<Path>) -> Result<AnimationSkeleton, String> {
        let (text, file) = super::read(path.as_ref())?;
        AnimationSkeleton::from_str(&text, &file)
    }

    /// Reads a skeleton from the text of a `.tof` file called `file` (for error messages; its
    /// stem names the skeleton). An error names the file, the line and the field of a joint
    /// named twice, a parent that names no joint and a parent listed after its child.
    pub fn from_str(text: &str, file: &str) -> Result<AnimationSkeleton, String> {
        let doc = Document::parse(text, file)?;
        let root = doc.root()?;
        if root.obj.type_name != "Skeleton" {
            return Err(super::object_error(&root, "expected Skeleton"));
        }
        let views = root.inlines("mJoints")?;
        if views.is_empty() {
            return Err(root.error("mJoints", "the skeleton has no joint"));
        }
        let names = (views.iter().map(|v| v.string("mName"))).collect::<Result<Vec<_>, _>>()?;
        let mut joints = Vec::with_capacity(views.len());
        for (i, (v, &name)) in views.iter().zip(&names).enumerate() {
            if name.is_empty() {
                return Err(v.error("mName", "a joint has no name"));
            }
            if let Some(first) = names[..i].iter().position(|n| *n == name) {
                let msg = format!("{name:?} also names joint {first}");
                return Err(v.error("mName", &msg));
            }
            let parent_name = v.string("mParentName")?;
            let parent = match names[..i].iter().position(|n| *n == parent_name) {
                Some(p) => Some(p),
                None if parent_name.is_empty() => None,
                None if parent_name == name => {
                    return Err(v.error("mParentName", "a joint is its own parent"))
                }
                None => {
                    let msg = match names[i..].contains(&parent_name) {
                        true => format!("the parent {parent_name:?} is listed after its child"),
                        false => format!("no joint is named {parent_name:?}"),
                    };
                    return Err(v.error("mParentName", &msg));
                }
            };
            let name = name.to_string();
            joints.push(SkeletonJoint { name, parent });
        }
        Ok(AnimationSkeleton {
            name: super::stem(file),
            joints,
        })
    }

    /// The index of joint `name`.
    pub fn joint_index(&self, name: &str) -> Option<usize> {
        self.joints.iter().position(|j| j.name == name)
    }

    /// Whether joint `ancestor` is joint `joint` or one of its ancestors.
    pub fn is_ancestor(&self, ancestor: usize, joint: usize) -> bool {
        let mut at = Some(joint);
        while let Some(j) = at {
            if j == ancestor {
                return true;
            }
            // parents come first: a parent index at or above the joint's ends the walk
            at = self
                .joints
                .get(j)
                .and_then(|joint| joint.parent.filter(|&p| p < j));
        }
        false
    }

    /// The joints from `from` to `to` along the parents, `from` first: an error unless both
    /// are joints and `from` is an ancestor of `to`.
    pub fn chain(&self, from: &str, to: &str) -> Result<Vec<usize>, String> {
        let index = |name: &str| {
            (self.joint_index(name))
                .ok_or_else(|| format!("the skeleton {} has no joint {name:?}", self.name))
        };
        let (from_index, to_index) = (index(from)?, index(to)?);
        let mut chain = vec![to_index];
        while chain[chain.len() - 1] != from_index {
            match self.joints[chain[chain.len() - 1]].parent {
                Some(p) => chain.push(p),
                None => {
                    let name = &self.name;
                    return Err(format!("{from:?} is not an ancestor of {to:?} in {name}"));
                }
            }
        }
        chain.reverse();
        Ok(chain)
    }

    /// The spine chain from `from` to `to` (see [`AnimationSkeleton::chain`]): an error unless
    /// it has [`BONES`] joints, the bones the §6 methods pose.
    pub fn spine_chain(&self, from: &str, to: &str) -> Result<[usize; BONES], String> {
        self.chain(from, to)?.try_into().map_err(|c: Vec<usize>| {
            let n = c.len();
            format!("the chain from {from:?} to {to:?} has {n} joints; a spine has {BONES}")
        })
    }

    /// Each joint's local transform in `pose` (a clip; its keys at time 0): an error naming
    /// the first joint the clip has no key for.
    pub fn locals_from(&self, pose: &Animation) -> Result<Vec<Iso>, String> {
        let keys = pose.sample(0.0);
        let local = |joint: &SkeletonJoint| {
            let key = keys.iter().find(|(name, ..)| *name == joint.name);
            let (_, translation, rotation) = key.ok_or_else(|| {
                let (clip, skeleton) = (&pose.name, &self.name);
                format!(
                    "the pose {clip} has no key for the joint {:?} of {skeleton}",
                    joint.name
                )
            })?;
            Ok(Iso::new(*translation, *rotation))
        };
        self.joints.iter().map(local).collect()
    }

    /// World poses from local transforms, in joint order: `world = parent's world * local`.
    pub fn world_from_local(&self, locals: &[Iso]) -> Vec<Iso> {
        let mut world: Vec<Iso> = Vec::with_capacity(self.joints.len());
        for (joint, &local) in self.joints.iter().zip(locals) {
            world.push(match joint.parent {
                Some(p) if p < world.len() => world[p] * local,
                _ => local,
            });
        }
        world
    }

    /// The first joint below `joint` (in joint order) for which `has` holds.
    fn anchor(&self, joint: usize, has: impl Fn(usize) -> bool) -> Option<usize> {
        (joint + 1..self.joints.len()).find(|&j| has(j) && self.is_ancestor(joint, j))
    }

    /// Every joint's world pose at the handover, from the parts' world poses `parts` (in
    /// `rig`'s part order) and the joints' neutral local transforms (see the module docs).
    pub fn handover_poses(&self, neutral_locals: &[Iso], rig: &Rig, parts: &[Iso]) -> Vec<Iso> {
        let part_pose = |j: usize| {
            rig.part_index(&self.joints[j].name)
                .and_then(|p| parts.get(p))
        };
        let neutral = self.world_from_local(neutral_locals);
        let mut world: Vec<Iso> = Vec::with_capacity(self.joints.len());
        for (i, joint) in self.joints.iter().enumerate() {
            let local = neutral_locals.get(i).copied().unwrap_or(Iso::IDENTITY);
            world.push(match (part_pose(i), joint.parent) {
                (Some(&pose), _) => pose,
                (None, Some(p)) if p < i => world[p] * local,
                (None, _) => match self.anchor(i, |j| part_pose(j).is_some()) {
                    Some(j) => *part_pose(j).unwrap_or(&neutral[j]) * neutral[j].inverse() * local,
                    None => local,
                },
            });
        }
        world
    }
}

/// How one joint is posed each frame.
#[derive(Clone, Copy, Debug)]
enum Drive {
    /// The spine skeleton's bone `k`.
    Bone(usize),
    /// Rigidly with a body: the joint's pose in the body's frame.
    Body(BodyId, Iso),
    /// The parent's world pose times this local transform.
    Parent(usize, Iso),
    /// Where it stood at the handover: a root with no body below it.
    Still(Iso),
}

/// A character at its handover: the rig, its parts' world poses and each part's body.
#[derive(Clone, Copy, Debug)]
pub struct Handover<'a> {
    /// The rig whose parts the character's bodies are.
    pub rig: &'a Rig,
    /// The parts' world poses at the handover, in the rig's part order.
    pub parts: &'a [Iso],
    /// Each part's body, in the rig's part order; `None` for a part the spine removed.
    pub bodies: &'a [Option<BodyId>],
}

/// An animation skeleton attached to a character's bodies at the handover, posing all its
/// joints back from the physics each frame (see the module docs).
#[derive(Clone, Debug)]
pub struct MappedSkeleton {
    names: Vec<String>,
    parents: Vec<Option<usize>>,
    drives: Vec<Drive>,
    chain: [usize; BONES],
    spine: Skeleton,
    at_handover: Vec<Iso>,
}

impl MappedSkeleton {
    /// Attaches `skeleton` (its neutral local transforms `neutral_locals`) to the character
    /// `handover` describes, the bodies in `world` standing at the handover. `region` names
    /// the spine's end joints, lower first, whose chain must have [`BONES`] joints and whose
    /// ends must have bodies; `rod` is the index of the rod constraint joining them, if any.
    pub fn new(
        world: &World,
        skeleton: &AnimationSkeleton,
        neutral_locals: &[Iso],
        handover: &Handover,
        region: (&str, &str),
        rod: Option<usize>,
    ) -> Result<MappedSkeleton, String> {
        let (rig, joints) = (handover.rig, &skeleton.joints);
        let ordered = |(i, joint): (usize, &SkeletonJoint)| joint.parent.is_none_or(|p| p < i);
        if !joints.iter().enumerate().all(ordered) {
            return Err(format!(
                "the skeleton {} lists a parent after its child",
                skeleton.name
            ));
        }
        if neutral_locals.len() != joints.len() {
            let (n, m) = (neutral_locals.len(), joints.len());
            return Err(format!("{n} neutral transforms for {m} joints"));
        }
        let parts = rig.parts.len();
        if handover.parts.len() != parts || handover.bodies.len() != parts {
            return Err(format!(
                "the handover does not give all {parts} parts of the rig"
            ));
        }
        let at_handover = skeleton.handover_poses(neutral_locals, rig, handover.parts);
        let chain = skeleton.spine_chain(region.0, region.1)?;
        let body_of = |j: usize| {
            let part = rig.part_index(&joints[j].name)?;
            handover.bodies[part]
        };
        let body_pose = |id: BodyId| Iso::new(world.body(id).position, world.body(id).orientation);
        let end_body = |end: usize| {
            let name = &joints[end].name;
            body_of(end).ok_or_else(|| format!("the spine's end {name:?} has no body"))
        };
        let lower = end_body(chain[0])?;
        end_body(chain[BONES - 1])?;
        // a bone without a body of its own follows the chain's nearest one along the chain,
        // the lower on a tie (the part whose segment holds the bone)
        let bones: [(BodyId, Iso); BONES] = std::array::from_fn(|k| {
            let with_body = (0..BONES).filter_map(|m| Some((m, body_of(chain[m])?)));
            let nearest = with_body.min_by_key(|&(m, _)| (m.abs_diff(k), m > k));
            (nearest.map_or(lower, |(_, id)| id), at_handover[chain[k]])
        });
        let spine = Skeleton::new(world, &bones, rod)?;
        let drives = (0..joints.len())
            .map(|i| {
                let follow = |id: BodyId| Drive::Body(id, body_pose(id).inverse() * at_handover[i]);
                if let Some(k) = chain.iter().position(|&c| c == i) {
                    return Drive::Bone(k);
                }
                if let Some(id) = body_of(i) {
                    return follow(id);
                }
                match joints[i].parent {
                    Some(p) if rig.part_index(&joints[i].name).is_none() => {
                        Drive::Parent(p, neutral_locals[i])
                    }
                    Some(p) => Drive::Parent(p, at_handover[p].inverse() * at_handover[i]),
                    None => match skeleton.anchor(i, |j| body_of(j).is_some()) {
                        Some(j) => body_of(j).map_or(Drive::Still(at_handover[i]), follow),
                        None => Drive::Still(at_handover[i]),
                    },
                }
            })
            .collect();
        Ok(MappedSkeleton {
            names: joints.iter().map(|j| j.name.clone()).collect(),
            parents: joints.iter().map(|j| j.parent).collect(),
            drives,
            chain,
            spine,
            at_handover,
        })
    }

    /// The joints' names, in joint order.
    pub fn names(&self) -> &[String] {
        &self.names
    }

    /// Each joint's parent index (lower than its own), in joint order; `None` for a root.
    pub fn parents(&self) -> &[Option<usize>] {
        &self.parents
    }

    /// The spine chain's joints, lower end first: the bones of [`MappedSkeleton::spine`].
    pub fn chain(&self) -> &[usize; BONES] {
        &self.chain
    }

    /// The spine's bones, posed and measured by each [`BoneMethod`].
    pub fn spine(&self) -> &Skeleton {
        &self.spine
    }

    /// Every joint's world pose at the handover.
    pub fn at_handover(&self) -> &[Iso] {
        &self.at_handover
    }

    /// Every joint's world pose from the bodies in `world`, the spine posed by `method`.
    pub fn pose(&self, world: &World, method: BoneMethod) -> Vec<Iso> {
        let mut poses = Vec::with_capacity(self.drives.len());
        self.pose_into(world, method, &mut poses);
        poses
    }

    /// [`MappedSkeleton::pose`] into `poses`, reusing its storage.
    pub fn pose_into(&self, world: &World, method: BoneMethod, poses: &mut Vec<Iso>) {
        let bones = self.spine.pose(world, method);
        poses.clear();
        for drive in &self.drives {
            let pose = match *drive {
                Drive::Bone(k) => Iso::new(bones.origins[k], bones.rotations[k]),
                Drive::Body(id, offset) => {
                    let body = world.body(id);
                    Iso::new(body.position, body.orientation) * offset
                }
                // parents come first, so the parent's pose is already in place
                Drive::Parent(p, local) => poses[p] * local,
                Drive::Still(pose) => pose,
            };
            poses.push(pose);
        }
    }
}
