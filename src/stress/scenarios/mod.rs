//! The cases of the stability suite and the scenes they build, one per [`Method`]. See the
//! module docs of [`crate::stress`] for what each case stresses and how methods map onto it.

use super::Method;
use crate::constraint::JointFlavour;
use crate::lab::Lab;
use crate::ragdoll::{SpineKind, TOTAL_MASS};
use crate::world::Settings;

mod chain;
mod scenes;

use scenes::build;

/// One scene of the suite with its time step, iterations and length.
#[derive(Clone, Debug)]
pub struct Case {
    /// Case name, in the suite's table and its recordings' names.
    pub name: &'static str,
    /// One line on what the case does.
    pub description: &'static str,
    /// What the case builds.
    pub scenario: Scenario,
    /// Frame time step (s).
    pub dt: f32,
    /// Solver iterations per substep.
    pub iterations: u32,
    /// Simulated time (s).
    pub seconds: f32,
}

impl Case {
    /// Frames to run: `seconds / dt`, rounded, at least 1.
    pub fn frames(&self) -> u32 {
        (self.seconds / self.dt).round().max(1.0) as u32
    }

    /// Builds the lab for this method and the number of frames to run, or None when the
    /// case does not apply to the method (a chain has no spine, so `single` skips it).
    pub fn build(&self, method: Method) -> Option<(Lab, u32)> {
        self.build_full(method).map(|b| (b.lab, b.frames))
    }

    /// [`Case::build`] with what the verdict needs to know about the scene.
    pub fn build_full(&self, method: Method) -> Option<Built> {
        let settings = Settings {
            dt: self.dt,
            iterations: self.iterations,
            ..Settings::default()
        };
        build(self.scenario, settings, self.frames(), method)
    }
}

const HZ60: f32 = 1.0 / 60.0;

const fn slump(tilt_deg: f32, stiff_spine: bool, forearm_mass_divisor: f32) -> Scenario {
    Scenario::Slump {
        tilt_deg,
        stiff_spine,
        forearm_mass_divisor,
    }
}

/// The paper's passive bending pose.
const SLUMP: Scenario = slump(8.0, false, 1.0);

/// The fixed suite, in table order.
pub fn suite() -> Vec<Case> {
    #[rustfmt::skip]
    let cases = [
        ("baseline", "passive bending at 60 Hz, 20 iterations: the reference",
            SLUMP, HZ60, 20, 4.0),
        ("dt_1_30", "passive bending at dt = 1/30 s",
            SLUMP, 1.0 / 30.0, 20, 4.0),
        ("dt_1_15", "passive bending at dt = 1/15 s",
            SLUMP, 1.0 / 15.0, 20, 4.0),
        ("iterations_2", "passive bending with 2 iterations",
            SLUMP, HZ60, 2, 4.0),
        ("iterations_1", "passive bending with 1 iteration",
            SLUMP, HZ60, 1, 4.0),
        ("heavy_hand_100", "pelvis fixed, 100 forearm masses (167 kg) held in the left hand",
            Scenario::HeavyHand { mass_ratio: 100.0 }, HZ60, 20, 4.0),
        ("heavy_hand_1000", "pelvis fixed, 1000 forearm masses (1.67 t) held in the left hand",
            Scenario::HeavyHand { mass_ratio: 1000.0 }, HZ60, 20, 4.0),
        ("light_forearms_100", "passive bending, both forearms 100 times lighter (17 g)",
            slump(8.0, false, 100.0), HZ60, 20, 4.0),
        ("light_forearms_1000", "passive bending, both forearms 1000 times lighter (1.7 g)",
            slump(8.0, false, 1000.0), HZ60, 20, 4.0),
        ("chain_40", "40 links (4 m) released from horizontal; rod: 40 rods, same length",
            Scenario::Chain { links: 40, horizontal: true, stretch_m: 0.0 }, HZ60, 20, 4.0),
        ("chain_40_stretched", "40 links hanging, each 5 cm from its joint at the start",
            Scenario::Chain { links: 40, horizontal: false, stretch_m: 0.05 }, HZ60, 20, 4.0),
        ("stiff_spine_dt_1_30", "stiff spine (rod alpha_b = alpha_t = 1) tilted 30 deg, dt = 1/30 s",
            slump(30.0, true, 1.0), 1.0 / 30.0, 20, 4.0),
        ("stiff_spine_dt_1_15", "stiff spine (rod alpha_b = alpha_t = 1) tilted 30 deg, dt = 1/15 s",
            slump(30.0, true, 1.0), 1.0 / 15.0, 20, 4.0),
        ("projectile_50", "contacts: a 20 kg sphere at 50 m/s hits a standing ragdoll's chest",
            Scenario::Projectile { mass: 20.0, speed: 50.0 }, HZ60, 20, 3.0),
        ("bent_near_pi", "pelvis fixed, spine bent 175 deg (joint spines: 74, their limit)",
            Scenario::BentSpine { psi_deg: 175.0 }, HZ60, 20, 3.0),
        ("hanging_near_zero", "hung by the head, spine bent 0.057 deg (rod psi = 1e-3 rad)",
            Scenario::Hanging { psi_deg: 0.057 }, HZ60, 20, 3.0),
    ];
    cases
        .into_iter()
        .map(
            |(name, description, scenario, dt, iterations, seconds)| Case {
                name,
                description,
                scenario,
                dt,
                iterations,
                seconds,
            },
        )
        .collect()
}

/// Mass of the reference humanoid's forearm and hand (kg), humanoid.md.
pub const FOREARM_MASS: f32 = 0.0223 * TOTAL_MASS;

/// What a case builds. Every ragdoll scene uses the same spine stiffness, the pair that makes
/// both spines slump about equally in the passive bending scene: spine springs of relaxation
/// 0.1 for `chain3` and `single`, alpha_b = 0.005 and alpha_t = 0.5 for `rod`; "stiff" means
/// springs of relaxation 1 (hard angular targets) and alpha_b = alpha_t = 1.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Scenario {
    /// Passive bending (paper Fig. 2): pelvis fixed, upper body tilted forward by `tilt_deg`
    /// (spread equally over chain3's three joints), slumping under gravity. The forearms' mass
    /// is divided by `forearm_mass_divisor` (1: the reference humanoid).
    Slump {
        /// Forward tilt of the upper body at the start (deg).
        tilt_deg: f32,
        /// Springs of relaxation 1 and alpha_b = alpha_t = 1 instead of the suite's spine
        /// stiffness.
        stiff_spine: bool,
        /// Divisor of both forearms' mass (1: the reference humanoid).
        forearm_mass_divisor: f32,
    },
    /// Pelvis fixed, standing; a sphere of `mass_ratio` times the forearm's mass hangs from the
    /// left hand by a ball-and-socket (the method's joint flavour).
    HeavyHand {
        /// The sphere's mass over the forearm's.
        mass_ratio: f32,
    },
    /// `links` capsules of 10 cm and 1 kg hung from a fixed support, 4 m for 40 links: joined by
    /// ball-and-sockets (chain3 methods, their flavour) or by rods between the link centres
    /// (rod: alpha_b = 0, free bending like the joints; alpha_t = 0.5; the paper's length
    /// correction). `horizontal`: released from horizontal; otherwise hanging straight down,
    /// every link pulled `stretch_m` away from its joint (at 45 degrees to the chain, sideways
    /// alternately), so the errors add up along the chain.
    Chain {
        /// Number of links.
        links: u32,
        /// Released from horizontal; otherwise hanging straight down.
        horizontal: bool,
        /// Each link's pull away from its joint at the start (m).
        stretch_m: f32,
    },
    /// Contacts on, a floor, a free standing ragdoll hit in the chest by a sphere of `mass` kg
    /// flying at `speed` m/s from 1.5 m away.
    Projectile {
        /// Sphere mass (kg).
        mass: f32,
        /// Sphere speed toward the chest (m/s).
        speed: f32,
    },
    /// Pelvis fixed, the spine bent forward by `psi_deg` at the start, its springs (rod:
    /// alpha_b, alpha_t) resting straight: the rod onto its arc, so its hard constraints hold;
    /// the joint spines as far as their swing limits allow (74 of 75 degrees), by equal
    /// rotations of their spine joints. The springs may give back the potential energy the
    /// bend took (the energy allowance).
    BentSpine {
        /// Forward bend of the spine at the start (deg); joint spines stop at their swing limits.
        psi_deg: f32,
    },
    /// Hung by the head (fixed), the rest of the body hanging below it at rest, the spine bent
    /// by `psi_deg` (the pelvis side moved onto the rod's arc, or the spine joints rotated).
    Hanging {
        /// Bend of the spine at the start (deg).
        psi_deg: f32,
    },
}

/// A scene ready to run, with what the verdict needs to know about it.
pub struct Built {
    /// The scene's world and ragdolls.
    pub lab: Lab,
    /// Frames to run.
    pub frames: u32,
    /// Whether everything should be nearly at rest by the end of the run.
    pub settles: bool,
    /// Energy (J) the scene may gain legitimately: the potential energy hidden by its initial
    /// joint errors (a pre-stretched chain rises when its joints close) or taken by a bend
    /// its springs will undo.
    pub energy_allowance: f32,
}

const SPINE_SPRING: f32 = 0.1;
const ROD_ALPHA_BEND: f32 = 0.005;
const ROD_ALPHA_TWIST: f32 = 0.5;

impl Method {
    /// The ragdoll spine this method builds.
    pub fn spine(self) -> SpineKind {
        match self {
            Method::Chain3Cheap | Method::Chain3Exact => SpineKind::Chain3,
            Method::Rod => SpineKind::Rod,
            Method::Single => SpineKind::Single,
        }
    }

    /// Ball-and-socket flavour: cheap only for `chain3-cheap`; the rod and single spines use
    /// exact limb joints, so they differ from `chain3-exact` in the spine alone.
    pub fn joint_flavour(self) -> JointFlavour {
        match self {
            Method::Chain3Cheap => JointFlavour::Cheap,
            _ => JointFlavour::Exact,
        }
    }
}
