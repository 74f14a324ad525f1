//! The documented bounds of a scene's numbers (docs/scene-format.md): every number is
//! finite (where infinity means nothing) and within a range that keeps the simulation in f32
//! and the run finite. A value outside names its field; [`check_drop`] runs before the `[drop]`
//! block is expanded, so a huge `count` is refused instead of allocated.

use super::locate::Seg;
use super::{BodyDef, CharacterDef, DropDef, JointDef, RagdollDef, SceneDef};

pub use crate::solver::{MAX_CONTACT_STACKING, MAX_DT, MAX_ITERATIONS, MAX_SUBSTEPS};
/// Frames per run, at most (46 h at 60 Hz).
pub const MAX_FRAMES: u32 = 10_000_000;
/// Worker threads of the solver's pool, at most (`--threads`).
pub const MAX_THREADS: u64 = 1024;
/// Ragdolls a `[drop]` block makes, at most.
pub const MAX_DROP_COUNT: usize = 10_000;
/// Bodies the `[[tile]]` groups expand to, all together, at most.
pub const MAX_TILE_BODIES: u64 = 100_000;
/// Positions and anchors lie within this distance of the origin (m).
pub const MAX_COORDINATE: f32 = 1e5;
/// Sizes (radii, half extents, lengths) at most (m).
pub const MAX_SIZE: f32 = 1e3;
/// Angles in degrees at most, in magnitude.
pub const MAX_DEGREES: f32 = 1e4;
/// Gravity at most (m/s^2).
pub const MAX_GRAVITY: f32 = 1e3;
/// External force at most (N).
pub const MAX_FORCE: f32 = 1e7;
/// Mass at most (kg) and density at most (kg/m^3).
pub const MAX_MASS: f32 = 1e9;
/// A clip time at most (s).
pub const MAX_CLIP_TIME: f32 = 1e4;
/// Contact margin at most (m).
pub const MAX_CONTACT_MARGIN: f32 = 1.0;

pub(super) type Failure = (Vec<Seg>, String);

fn key(prefix: &[Seg], parts: &[Seg]) -> Vec<Seg> {
    prefix.iter().chain(parts).cloned().collect()
}

fn k(name: &str) -> Seg {
    Seg::Key(name.into())
}

/// `values` finite with magnitudes at most `max` (`what` says the unit).
pub(super) fn within(values: &[f32], max: f32, what: &str) -> Result<(), String> {
    match values.iter().find(|v| !(v.abs() <= max)) {
        Some(v) => Err(format!(
            "must be finite {what} of magnitude at most {max:e}, got {v}"
        )),
        None => Ok(()),
    }
}

/// The method settings (also a variant's, applied: `prefix` its path).
pub fn check_settings(d: &SceneDef, prefix: &[Seg]) -> Result<(), Failure> {
    let at = |name: &str| key(prefix, &[k(name)]);
    if d.frames > MAX_FRAMES {
        return Err((
            at("frames"),
            format!("must be at most {MAX_FRAMES}, got {}", d.frames),
        ));
    }
    within(&d.gravity, MAX_GRAVITY, "accelerations (m/s^2)").map_err(|m| (at("gravity"), m))?;
    if !(0.0..=MAX_CONTACT_MARGIN).contains(&d.contact_margin) {
        return Err((
            at("contact_margin"),
            format!(
                "must be a distance from 0 to {MAX_CONTACT_MARGIN} m, got {}",
                d.contact_margin
            ),
        ));
    }
    for (name, value) in [
        ("max_speed", d.max_speed),
        ("max_angular_speed", d.max_angular_speed),
    ] {
        if value.is_nan() {
            return Err((
                at(name),
                "must be a positive number (or inf), got NaN".into(),
            ));
        }
    }
    Ok(())
}

/// The `[drop]` block, before it makes its ragdolls.
pub fn check_drop(drop: &DropDef) -> Result<(), Failure> {
    let at = |name: &str| vec![k("drop"), k(name)];
    if !(1..=MAX_DROP_COUNT).contains(&drop.count) {
        return Err((
            at("count"),
            format!(
                "must lie in [1, {MAX_DROP_COUNT}] ragdolls, got {}",
                drop.count
            ),
        ));
    }
    for (name, value) in [("columns", drop.columns), ("rows", drop.rows)] {
        if value == 0 {
            return Err((at(name), "must be at least 1".into()));
        }
    }
    within(&drop.first, MAX_COORDINATE, "coordinates (m)").map_err(|m| (at("first"), m))?;
    within(&drop.spacing, MAX_SIZE, "distances (m)").map_err(|m| (at("spacing"), m))?;
    if !(0.0..=180.0).contains(&drop.max_tip) {
        return Err((
            at("max_tip"),
            format!("must be an angle from 0 to 180 deg, got {}", drop.max_tip),
        ));
    }
    let message = match drop.character.is_some() {
        true if !drop.spine.fits_character() => Some("a character takes rig, rod or single"),
        false if !drop.spine.fits_humanoid() => Some("a ragdoll takes chain3, rod or single"),
        _ => None,
    };
    if let Some(m) = message {
        return Err((at("spine"), format!("{m}, got {}", drop.spine)));
    }
    if drop.character.as_ref().is_some_and(|c| c.clips.is_empty()) {
        let path = vec![k("drop"), k("character"), k("clips")];
        return Err((path, "names no clip; give at least one".into()));
    }
    Ok(())
}

/// A ragdoll's numbers (`at(field)` is its field's path).
pub fn check_ragdoll(r: &RagdollDef, at: impl Fn(&str) -> Vec<Seg>) -> Result<(), Failure> {
    check_placement(&r.position, &r.rotation, &r.pose, &at)?;
    for (part, force) in &r.forces {
        within(force, MAX_FORCE, "forces (N)").map_err(|m| {
            let mut path = at("forces");
            path.push(k(part));
            (path, m)
        })?;
    }
    Ok(())
}

/// A character's numbers: placement, extra joint turns, clip time.
pub fn check_character(c: &CharacterDef, at: impl Fn(&str) -> Vec<Seg>) -> Result<(), Failure> {
    check_placement(&c.position, &c.rotation, &c.pose, &at)?;
    if !(0.0..=MAX_CLIP_TIME).contains(&c.time) {
        let message = format!("must be a time from 0 to {MAX_CLIP_TIME} s, got {}", c.time);
        return Err((at("time"), message));
    }
    if let Some(from) = c.play_from {
        if !(0.0..=c.time).contains(&from) {
            let message = format!("must be a time from 0 to `time` ({} s), got {from}", c.time);
            return Err((at("play_from"), message));
        }
    }
    Ok(())
}

/// Frames a clip may play before its handover (a minute at 60 Hz): the played poses are kept.
pub const MAX_PLAYBACK_FRAMES: f32 = 3600.0;

/// A character's played clip, in frames of `dt`, within [`MAX_PLAYBACK_FRAMES`].
pub fn check_playback(
    c: &CharacterDef,
    dt: f32,
    at: impl Fn(&str) -> Vec<Seg>,
) -> Result<(), Failure> {
    let Some(from) = c.play_from else {
        return Ok(());
    };
    let frames = ((c.time - from) / dt).round();
    if frames > MAX_PLAYBACK_FRAMES {
        let message = format!(
            "plays the clip for {frames} frames of dt before the handover, at most {MAX_PLAYBACK_FRAMES}"
        );
        return Err((at("play_from"), message));
    }
    if c.clip.is_none() {
        return Err((
            at("play_from"),
            "plays a clip, and the character names none".into(),
        ));
    }
    Ok(())
}

/// A placement (position, rotation vector in degrees) and extra joint turns (degrees), each
/// within its bounds.
fn check_placement(
    position: &[f32; 3],
    rotation: &[f32; 3],
    pose: &std::collections::BTreeMap<String, [f32; 3]>,
    at: &impl Fn(&str) -> Vec<Seg>,
) -> Result<(), Failure> {
    within(position, MAX_COORDINATE, "coordinates (m)").map_err(|m| (at("position"), m))?;
    within(rotation, MAX_DEGREES, "angles (deg)").map_err(|m| (at("rotation"), m))?;
    for (joint, turn) in pose {
        within(turn, MAX_DEGREES, "angles (deg)").map_err(|m| {
            let mut path = at("pose");
            path.push(k(joint));
            (path, m)
        })?;
    }
    Ok(())
}

/// A body's numbers, beyond its shape's and mass's signs (`check_body` in the parent).
pub fn check_body(
    b: &BodyDef,
    max_speed: f32,
    max_angular_speed: f32,
) -> Result<(), (&'static str, String)> {
    within(&b.position, MAX_COORDINATE, "coordinates (m)").map_err(|m| ("position", m))?;
    within(&b.rotation, MAX_DEGREES, "angles (deg)").map_err(|m| ("rotation", m))?;
    for (name, value) in [("radius", b.radius), ("half_height", b.half_height)] {
        if let Some(v) = value {
            within(&[v], MAX_SIZE, "a size (m)").map_err(|m| (name, m))?;
        }
    }
    if let Some(h) = &b.half_extents {
        within(h, MAX_SIZE, "sizes (m)").map_err(|m| ("half_extents", m))?;
    }
    for (name, value) in [("mass", b.mass), ("density", b.density)] {
        if let Some(v) = value {
            within(&[v], MAX_MASS, "a mass (kg) or density (kg/m^3)").map_err(|m| (name, m))?;
        }
    }
    // a starting state the explosion check would refuse on the first frame
    let speed = glam::Vec3::from(b.velocity).length();
    if !(speed <= max_speed) {
        return Err((
            "velocity",
            format!("must be finite and at most max_speed = {max_speed} m/s, got {speed} m/s"),
        ));
    }
    let spin = glam::Vec3::from(b.angular_velocity).length();
    if !(spin <= max_angular_speed) {
        return Err((
            "angular_velocity",
            format!(
                "must be finite and at most max_angular_speed = {max_angular_speed} rad/s, got \
                 {spin} rad/s"
            ),
        ));
    }
    Ok(())
}

/// A joint's numbers.
pub fn check_joint(j: &JointDef) -> Result<(), (&'static str, String)> {
    within(&j.anchor, MAX_COORDINATE, "coordinates (m)").map_err(|m| ("anchor", m))?;
    within(&j.axis, MAX_COORDINATE, "components").map_err(|m| ("axis", m))?;
    if let Some(s) = j.swing {
        within(&[s], 180.0, "an angle (deg)").map_err(|m| ("swing", m))?;
    }
    for (name, range) in [("twist", j.twist), ("hinge", j.hinge)] {
        if let Some(r) = range {
            within(&r, 360.0, "angles (deg)").map_err(|m| (name, m))?;
        }
    }
    Ok(())
}

/// Bodies a tile group makes: its copies times its bodies.
pub fn tile_bodies(repeat: [u32; 2], bodies: usize) -> u64 {
    repeat[0] as u64 * repeat[1] as u64 * bodies as u64
}

/// The scene's `name`, used as a file name under the output folder: no path separators, no
/// `..`, nothing a shell or a file system treats specially at its start.
pub fn check_scene_name(name: &str) -> Result<(), String> {
    let bad = name.is_empty()
        || name.contains(['/', '\\', '\0'])
        || name.contains("..")
        || name.starts_with(['.', '-', '~']);
    if bad {
        return Err(format!(
            "\"{name}\" cannot name a recording file: use letters, digits, '_' and '-', no path \
             separators or '..'"
        ));
    }
    Ok(())
}
