//! The verdict's criteria: the thresholds, the first one a run trips, and the verdict itself
//! (the measurements behind each threshold are in the [`crate::stress`] module docs).

use super::{Measures, Verdict};

/// Thresholds of the verdict; the [`crate::stress`] module docs give the measurements behind
/// each default.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Criteria {
    /// Exploded: energy growth held over the last second above this.
    pub exploded_final_energy_growth: f32,
    /// Exploded: peak speed above this multiple of the scene's speed reference.
    pub exploded_speed_factor: f32,
    /// Exploded (torn apart): largest dislocation, mean over the last second (cm), above this.
    pub exploded_residual_cm: f32,
    /// Jittering: energy growth at any moment above this (a pop).
    pub jitter_energy_growth: f32,
    /// Jittering: energy growth held over the last second above this.
    pub jitter_final_energy_growth: f32,
    /// Jittering: largest dislocation, mean over the last second (cm), above this.
    pub jitter_residual_cm: f32,
    /// Jittering: a settling scene's fastest point, mean over the last second (m/s), above this.
    pub jitter_final_speed: f32,
    /// Jittering: shake, mean over the last second (m/s), above this.
    pub jitter_shake: f32,
}

impl Default for Criteria {
    fn default() -> Self {
        Criteria {
            exploded_final_energy_growth: 1.0,
            exploded_speed_factor: 5.0,
            exploded_residual_cm: 50.0,
            jitter_energy_growth: 0.5,
            jitter_final_energy_growth: 0.1,
            jitter_residual_cm: 5.0,
            jitter_final_speed: 0.2,
            jitter_shake: 0.1,
        }
    }
}

/// The first criterion a run trips, most severe first, with its verdict and a short reason;
/// None when the run is stable.
pub fn tripped(m: &Measures, c: &Criteria) -> Option<(Verdict, String)> {
    use Verdict::{Exploded, Jittering};
    if let Some(message) = &m.failed {
        // "frame N: body ..." -> "frame N"
        let frame = message.split(':').next().unwrap_or(message);
        return Some((Exploded, frame.to_string()));
    }
    let numbers = [
        m.energy_growth,
        m.final_energy_growth,
        m.peak_speed,
        m.final_speed,
        m.max_residual_cm,
        m.mean_residual_cm,
        m.mean_angular_rad,
        m.shake,
    ];
    if numbers.iter().any(|x| !x.is_finite()) {
        return Some((Exploded, "NaN".into()));
    }
    let checks = [
        (
            m.final_energy_growth > c.exploded_final_energy_growth,
            Exploded,
            format!("energy kept +{:.2}", m.final_energy_growth),
        ),
        (
            m.peak_speed > c.exploded_speed_factor * m.speed_reference,
            Exploded,
            format!("peak {:.0} m/s", m.peak_speed),
        ),
        (
            m.mean_residual_cm > c.exploded_residual_cm,
            Exploded,
            format!("torn {:.0} cm", m.mean_residual_cm),
        ),
        (
            m.final_energy_growth > c.jitter_final_energy_growth,
            Jittering,
            format!("energy kept +{:.2}", m.final_energy_growth),
        ),
        (
            m.energy_growth > c.jitter_energy_growth,
            Jittering,
            format!("energy pop +{:.2}", m.energy_growth),
        ),
        (
            m.mean_residual_cm > c.jitter_residual_cm,
            Jittering,
            format!("residual {:.1} cm", m.mean_residual_cm),
        ),
        (
            m.settles && m.final_speed > c.jitter_final_speed,
            Jittering,
            format!("end speed {:.2} m/s", m.final_speed),
        ),
        (
            m.shake > c.jitter_shake,
            Jittering,
            format!("shake {:.2} m/s", m.shake),
        ),
    ];
    checks
        .into_iter()
        .find(|(hit, _, _)| *hit)
        .map(|(_, verdict, why)| (verdict, why))
}

/// The verdict of a run: a pure function of its measures.
pub fn verdict(m: &Measures, criteria: &Criteria) -> Verdict {
    tripped(m, criteria).map_or(Verdict::Stable, |(v, _)| v)
}
