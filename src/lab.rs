//! The lab: a [`World`] and what the experiments measure and draw on top of it.
//!
//! The world is physics only (bodies, constraints, contacts, settings). The lab adds the
//! ragdolls that group its bodies and constraints, their animation skeletons and their target
//! poses; metrics, observers, the recorder and the command line read them from here.

use crate::body::BodyId;
use crate::playback::Playback;
use crate::ragdoll::{build_humanoid, HumanoidSpec, Ragdoll};
use crate::world::{SimulationError, World};

/// A world and the ragdolls built in it.
#[derive(Clone, Debug)]
pub struct Lab {
    /// The physics: bodies, constraints, contacts and settings.
    pub world: World,
    /// Groups of the world's bodies and constraints, in build order.
    pub ragdolls: Vec<Ragdoll>,
    /// Clips played on characters before their handover, posed before each step.
    pub playbacks: Vec<Playback>,
}

impl Lab {
    /// A lab around `world`, with no ragdolls yet.
    pub fn new(world: World) -> Self {
        Lab {
            world,
            ragdolls: Vec::new(),
            playbacks: Vec::new(),
        }
    }

    /// Builds the humanoid into the world and keeps its ragdoll. Errors name the unknown joint
    /// or part.
    pub fn add_humanoid(&mut self, spec: &HumanoidSpec) -> Result<&Ragdoll, String> {
        let ragdoll = build_humanoid(&mut self.world, spec)?;
        self.ragdolls.push(ragdoll);
        Ok(self.ragdolls.last().expect("just pushed"))
    }

    /// The ragdoll that `body` belongs to, if any.
    pub fn ragdoll_of(&self, body: BodyId) -> Option<&Ragdoll> {
        self.ragdolls
            .iter()
            .find(|r| r.bodies.contains(&body.index()))
    }

    /// Advances the world one frame.
    pub fn step(&mut self) -> Result<(), SimulationError> {
        for playback in &mut self.playbacks {
            playback.pose(&mut self.world);
        }
        self.world.step()
    }
}
