//! Generated content: a `[drop]` block's ragdolls or characters and a `[[tile]]`'s copies,
//! made when the scene is parsed so that the checks and the build see plain `[[ragdoll]]`,
//! `[[character]]` and `[[body]]` entries.

use super::{BodyDef, CharacterDef, DropDef, RagdollDef, TileDef};
use crate::math::quat_from_degrees;

impl DropDef {
    /// The characters this block stands for, with a `character` table (else none).
    pub(super) fn expand_characters(&self) -> Vec<CharacterDef> {
        let Some(c) = &self.character else {
            return Vec::new();
        };
        let defaults = CharacterDef::default_alphas();
        (self.placements().into_iter().enumerate())
            .map(|(i, (name, position, rotation))| CharacterDef {
                name,
                rig: c.rig.clone(),
                clip: c.clips.get(i % c.clips.len().max(1)).cloned(),
                time: c.time,
                play_from: None,
                skeleton: None,
                skeleton_pose: None,
                position,
                rotation,
                pose: Default::default(),
                spine: self.spine,
                region: c.region.clone(),
                fixed: Vec::new(),
                joint_flavour: None,
                alpha_b: c.alpha_b.unwrap_or(defaults.0),
                alpha_t: c.alpha_t.unwrap_or(defaults.1),
                twist: Default::default(),
            })
            .collect()
    }

    /// The humanoids this block stands for, without a `character` table (else none).
    pub(super) fn expand(&self) -> Vec<RagdollDef> {
        if self.character.is_some() {
            return Vec::new();
        }
        (self.placements().into_iter())
            .map(|(name, position, rotation)| RagdollDef {
                name,
                spine: self.spine,
                joint_flavour: None,
                position,
                rotation,
                pose: Default::default(),
                fixed: Vec::new(),
                spine_spring: Some(0.05),
                limb_spring: None,
                alpha_b: None,
                alpha_t: None,
                bend_stiffness: None,
                bend_damping: None,
                twist_stiffness: None,
                twist_damping: None,
                twist: None,
                rod_length: None,
                bend_twist: None,
                forces: Default::default(),
                self_contacts: self.self_contacts,
            })
            .collect()
    }

    /// Each dropped item's name (`drop00`, or `drop000` for characters), position (m) and
    /// rotation vector (deg): on the grid, turned by a random yaw and tipped by a random angle
    /// from the seed.
    pub(super) fn placements(&self) -> Vec<(String, [f32; 3], [f32; 3])> {
        let mut state = self
            .seed
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        let mut random = move || {
            // 64-bit LCG (Knuth's MMIX constants), top 24 bits as a float in [0, 1)
            state = state
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            (state >> 40) as f32 / (1u64 << 24) as f32
        };
        let per_layer = (self.columns * self.rows).max(1);
        (0..self.count)
            .map(|i| {
                let (layer, cell) = (i / per_layer, i % per_layer);
                let (column, row) = (cell % self.columns.max(1), cell / self.columns.max(1));
                let position = [
                    self.first[0] + column as f32 * self.spacing[0],
                    self.first[1] + layer as f32 * self.spacing[1],
                    self.first[2] + row as f32 * self.spacing[2],
                ];
                let yaw = 360.0 * random();
                let tip = self.max_tip * random();
                let rotation = crate::math::rotation_vector(
                    quat_from_degrees([0.0, yaw, 0.0]) * quat_from_degrees([tip, 0.0, 0.0]),
                );
                let name = match self.character {
                    Some(_) => format!("drop{i:03}"),
                    None => format!("drop{i:02}"),
                };
                let degrees = (rotation * 180.0 / std::f32::consts::PI).to_array();
                (name, position, degrees)
            })
            .collect()
    }
}

impl TileDef {
    /// Name of copy `(i, k)` of the group's body `body`.
    pub(super) fn copy_name(&self, i: u32, k: u32, body: &str) -> String {
        format!("{}_{i}_{k}_{body}", self.name)
    }

    /// The bodies this tile stands for.
    pub(super) fn expand(&self) -> Vec<BodyDef> {
        let mut out =
            Vec::with_capacity(self.body.len() * (self.repeat[0] * self.repeat[1]) as usize);
        for i in 0..self.repeat[0] {
            for k in 0..self.repeat[1] {
                for b in &self.body {
                    let mut copy = b.clone();
                    copy.name = self.copy_name(i, k, &b.name);
                    copy.position[0] += i as f32 * self.spacing[0];
                    copy.position[2] += k as f32 * self.spacing[1];
                    out.push(copy);
                }
            }
        }
        out
    }
}
