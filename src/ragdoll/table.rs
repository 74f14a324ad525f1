//! The reference humanoid's tables (`shared/humanoid.md`): its parts' proportions and mass
//! shares, its joints' centres, frames and limits, and the part and joint names per spine.

use std::f32::consts::FRAC_PI_2;

use super::SpineKind;
use crate::math::Quat;
use crate::shape::Axis;

pub(super) struct Part {
    pub(super) name: &'static str,
    pub(super) axis: Axis,
    pub(super) half_height: f32,
    pub(super) radius: f32,
    pub(super) centre: [f32; 2],
    /// Share of the total mass (de Leva 1996).
    pub(super) mass_fraction: f32,
}

const fn part(
    name: &'static str,
    axis: Axis,
    half_height: f32,
    radius: f32,
    centre: [f32; 2],
    mass_fraction: f32,
) -> Part {
    Part {
        name,
        axis,
        half_height,
        radius,
        centre,
        mass_fraction,
    }
}

/// Total mass of the reference humanoid (kg).
pub const TOTAL_MASS: f32 = 75.0;

/// humanoid.md, bodies with the 3-joint spine. Parent parts come before their children.
pub(super) const PARTS: [Part; 13] = [
    part("pelvis", Axis::X, 0.070, 0.100, [0.0, 1.000], 0.1117),
    part("lower_spine", Axis::X, 0.090, 0.055, [0.0, 1.1125], 0.08165),
    part("upper_spine", Axis::X, 0.090, 0.055, [0.0, 1.2175], 0.08165),
    part("chest", Axis::X, 0.070, 0.120, [0.0, 1.385], 0.1596),
    part("head", Axis::Y, 0.040, 0.100, [0.0, 1.660], 0.0694),
    part("upper_arm_l", Axis::Y, 0.105, 0.045, [0.22, 1.290], 0.0271),
    part("upper_arm_r", Axis::Y, 0.105, 0.045, [-0.22, 1.290], 0.0271),
    part("forearm_l", Axis::Y, 0.180, 0.040, [0.22, 0.920], 0.0223),
    part("forearm_r", Axis::Y, 0.180, 0.040, [-0.22, 0.920], 0.0223),
    part("thigh_l", Axis::Y, 0.150, 0.070, [0.09, 0.730], 0.1416),
    part("thigh_r", Axis::Y, 0.150, 0.070, [-0.09, 0.730], 0.1416),
    part("shank_l", Axis::Y, 0.205, 0.050, [0.09, 0.255], 0.057),
    part("shank_r", Axis::Y, 0.205, 0.050, [-0.09, 0.255], 0.057),
];

/// Twist or hinge axis of a joint frame in the reference pose.
#[derive(Clone, Copy)]
pub(super) enum FrameAxis {
    Up,
    Down,
    /// +x (left): positive hinge angle swings the child backward (knee flexion).
    Left,
    /// -x: positive hinge angle swings the child forward (elbow flexion).
    Right,
}

impl FrameAxis {
    pub(super) fn rotation(self) -> Quat {
        match self {
            FrameAxis::Up => crate::math::quat_from_rotation_z(FRAC_PI_2),
            FrameAxis::Down => crate::math::quat_from_rotation_z(-FRAC_PI_2),
            FrameAxis::Left => Quat::IDENTITY,
            FrameAxis::Right => crate::math::quat_from_rotation_y(std::f32::consts::PI),
        }
    }
}

pub(super) struct JointDef {
    pub(super) name: &'static str,
    pub(super) parent: &'static str,
    pub(super) child: &'static str,
    pub(super) centre: [f32; 2],
    pub(super) axis: FrameAxis,
    /// Swing cone half-angle and symmetric twist range (deg), or hinge range (deg).
    pub(super) limit: LimitDef,
    pub(super) spine: bool,
}

#[derive(Clone, Copy)]
pub(super) enum LimitDef {
    Cone { swing: f32, twist: f32 },
    Hinge { min: f32, max: f32 },
}

const fn joint(
    name: &'static str,
    parent: &'static str,
    child: &'static str,
    centre: [f32; 2],
    axis: FrameAxis,
    limit: LimitDef,
    spine: bool,
) -> JointDef {
    JointDef {
        name,
        parent,
        child,
        centre,
        axis,
        limit,
        spine,
    }
}

const SPINE_CONE: LimitDef = LimitDef::Cone {
    swing: 25.0,
    twist: 15.0,
};

/// humanoid.md joints (chain3 spine first; `single`/`rod` replace the first three).
const CHAIN3_SPINE: [JointDef; 3] = [
    joint(
        "lumbosacral",
        "pelvis",
        "lower_spine",
        [0.0, 1.060],
        FrameAxis::Up,
        SPINE_CONE,
        true,
    ),
    joint(
        "thoracolumbar",
        "lower_spine",
        "upper_spine",
        [0.0, 1.165],
        FrameAxis::Up,
        SPINE_CONE,
        true,
    ),
    joint(
        "mid_thoracic",
        "upper_spine",
        "chest",
        [0.0, 1.270],
        FrameAxis::Up,
        SPINE_CONE,
        true,
    ),
];
const SINGLE_SPINE: JointDef = joint(
    "lumbosacral",
    "pelvis",
    "chest",
    [0.0, 1.060],
    FrameAxis::Up,
    LimitDef::Cone {
        swing: 75.0,
        twist: 45.0,
    },
    true,
);
const LIMBS: [JointDef; 9] = [
    joint(
        "neck",
        "chest",
        "head",
        [0.0, 1.520],
        FrameAxis::Up,
        LimitDef::Cone {
            swing: 45.0,
            twist: 45.0,
        },
        false,
    ),
    joint(
        "shoulder_l",
        "chest",
        "upper_arm_l",
        [0.22, 1.440],
        FrameAxis::Down,
        LimitDef::Cone {
            swing: 90.0,
            twist: 60.0,
        },
        false,
    ),
    joint(
        "shoulder_r",
        "chest",
        "upper_arm_r",
        [-0.22, 1.440],
        FrameAxis::Down,
        LimitDef::Cone {
            swing: 90.0,
            twist: 60.0,
        },
        false,
    ),
    joint(
        "elbow_l",
        "upper_arm_l",
        "forearm_l",
        [0.22, 1.140],
        FrameAxis::Right,
        LimitDef::Hinge {
            min: 0.0,
            max: 145.0,
        },
        false,
    ),
    joint(
        "elbow_r",
        "upper_arm_r",
        "forearm_r",
        [-0.22, 1.140],
        FrameAxis::Right,
        LimitDef::Hinge {
            min: 0.0,
            max: 145.0,
        },
        false,
    ),
    joint(
        "hip_l",
        "pelvis",
        "thigh_l",
        [0.09, 0.950],
        FrameAxis::Down,
        LimitDef::Cone {
            swing: 70.0,
            twist: 30.0,
        },
        false,
    ),
    joint(
        "hip_r",
        "pelvis",
        "thigh_r",
        [-0.09, 0.950],
        FrameAxis::Down,
        LimitDef::Cone {
            swing: 70.0,
            twist: 30.0,
        },
        false,
    ),
    joint(
        "knee_l",
        "thigh_l",
        "shank_l",
        [0.09, 0.510],
        FrameAxis::Left,
        LimitDef::Hinge {
            min: 0.0,
            max: 140.0,
        },
        false,
    ),
    joint(
        "knee_r",
        "thigh_r",
        "shank_r",
        [-0.09, 0.510],
        FrameAxis::Left,
        LimitDef::Hinge {
            min: 0.0,
            max: 140.0,
        },
        false,
    ),
];

/// Names of the joints a pose may rotate for this spine.
pub fn joint_names(spine: SpineKind) -> Vec<&'static str> {
    joint_defs(spine).map(|j| j.name).collect()
}

pub(super) fn joint_defs(spine: SpineKind) -> impl Iterator<Item = &'static JointDef> {
    let spine_joints: &'static [JointDef] = match spine {
        // (a scene's check turns `rig` away from the humanoid; built, it is the humanoid's own)
        SpineKind::Chain3 | SpineKind::Rig => &CHAIN3_SPINE,
        SpineKind::Single | SpineKind::Rod => std::slice::from_ref(&SINGLE_SPINE),
    };
    spine_joints.iter().chain(LIMBS.iter())
}

pub(super) fn has_part(spine: SpineKind, name: &str) -> bool {
    matches!(spine, SpineKind::Chain3 | SpineKind::Rig)
        || !matches!(name, "lower_spine" | "upper_spine")
}

/// Part names for this spine.
pub fn part_names(spine: SpineKind) -> Vec<&'static str> {
    PARTS
        .iter()
        .map(|p| p.name)
        .filter(|n| has_part(spine, n))
        .collect()
}
