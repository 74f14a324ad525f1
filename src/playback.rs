//! A clip played on a character's bodies before the handover (paper §6): kinematic bodies
//! that follow the animation frame by frame, then, at the handover frame, dynamic bodies at the
//! clip's pose with its velocities, as a game hands a character to physics when it is hit.
//!
//! Each frame before the handover every body is put where the clip has it at that frame and
//! given the velocity that carries it to the next frame's pose, so what it touches feels the
//! motion; at the handover frame the body is put at the clip's pose at the handover time and
//! becomes dynamic with the velocities the character was built with (the clip's, over one
//! keyframe centred there).

use crate::body::{BodyId, BodyKind};
use crate::math::{rotation_vector, Iso, Vec3};
use crate::world::World;

/// One character's clip, played until its handover frame.
#[derive(Clone, Debug)]
pub struct Playback {
    /// The character's bodies.
    bodies: Vec<BodyId>,
    /// Per frame up to the handover, each body's world pose.
    poses: Vec<Vec<Iso>>,
    /// Each body's linear and angular velocity at the handover.
    handover_velocities: Vec<(Vec3, Vec3)>,
    /// The frame the next step starts from.
    frame: usize,
}

impl Playback {
    /// A playback of `poses` (per frame up to and including the handover frame, each of
    /// `bodies`' world poses) on bodies built at the handover pose with the handover
    /// velocities; the bodies become kinematic at the first frame's pose.
    pub fn start(world: &mut World, bodies: Vec<BodyId>, poses: Vec<Vec<Iso>>) -> Playback {
        let handover_velocities = (bodies.iter())
            .map(|&id| {
                let b = world.body(id);
                (b.linear_velocity, b.angular_velocity)
            })
            .collect();
        let playback = Playback {
            bodies,
            poses,
            handover_velocities,
            frame: 0,
        };
        if playback.handover_frame() > 0 {
            for &id in &playback.bodies {
                world.body_mut(id).set_kind(BodyKind::Kinematic);
            }
        }
        playback.apply(world, 0);
        playback
    }

    /// The frame at which the bodies become dynamic.
    pub fn handover_frame(&self) -> usize {
        self.poses.len().saturating_sub(1)
    }

    /// Before a step: the bodies at this frame's pose, moving toward the next frame's, or at
    /// the handover frame made dynamic with the handover velocities; after it, nothing.
    pub fn pose(&mut self, world: &mut World) {
        if self.frame <= self.handover_frame() {
            self.apply(world, self.frame);
            self.frame += 1;
        }
    }

    fn apply(&self, world: &mut World, frame: usize) {
        let handover = self.handover_frame();
        let dt = world.settings.dt;
        for (k, &id) in self.bodies.iter().enumerate() {
            let now = self.poses[frame][k];
            let body = world.body_mut(id);
            body.set_pose(now.translation, now.rotation);
            if frame == handover {
                body.set_kind(BodyKind::Dynamic);
                (body.linear_velocity, body.angular_velocity) = self.handover_velocities[k];
            } else {
                let next = self.poses[frame + 1][k];
                body.linear_velocity = (next.translation - now.translation) / dt;
                let turn = (next.rotation * now.rotation.inverse()).normalize();
                body.angular_velocity = rotation_vector(turn) / dt;
            }
        }
    }
}
