//! Where a step's wall time goes, phase by phase (Box2D's `b2Profile`), so a user sees what a
//! scene's cost is made of: detection, the rows, the body passes, sleeping.

use std::time::Instant;

/// Wall time (s) of each phase of one step (or, summed, of a run), in the order of the
/// solver's step list; the substeps' phases are summed over the substeps.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Profile {
    /// 1. contact detection (broad and narrow phase); on several threads with the joints' and
    ///    rods' rows prepared beside it. Its pieces:
    ///    [`crate::contact::Contacts::detection_profile`].
    pub detect: f64,
    /// 2. rows per kind, coloured (on several threads the contact points' only).
    pub prepare: f64,
    /// 3.1-3.2 velocities, preview poses into the hot array, the rows' per-substep constants.
    pub integrate: f64,
    /// 3.3 the iterations, per kind.
    pub rods: f64,
    /// Ball-and-socket joints and dampers.
    pub joints: f64,
    /// Contact points.
    pub contacts: f64,
    /// 3.4 velocities from the previews, poses committed.
    pub commit: f64,
    /// 3.5 the contacts' velocity pass.
    pub velocity_pass: f64,
    /// 4. the health check: NaN, speeds, separations, penetrations.
    pub health: f64,
    /// 5. the sleep pass.
    pub sleep: f64,
    /// The whole step, timed where it runs (on a pool worker with several threads): the
    /// phases plus the moments between them. Not a phase; the caller's own timing adds the
    /// hand-over onto the pool, which no phase covers.
    pub step: f64,
}

impl Profile {
    /// The phases as (name, seconds), in step order.
    pub fn phases(&self) -> [(&'static str, f64); 10] {
        [
            ("detect", self.detect),
            ("prepare", self.prepare),
            ("integrate", self.integrate),
            ("rods", self.rods),
            ("joints", self.joints),
            ("contacts", self.contacts),
            ("commit", self.commit),
            ("velocity pass", self.velocity_pass),
            ("health", self.health),
            ("sleep", self.sleep),
        ]
    }

    /// The phases summed (s), without `step`.
    pub fn total(&self) -> f64 {
        self.phases().iter().map(|(_, s)| s).sum()
    }

    /// Adds `other`'s phases to these (a run's sum of steps).
    pub fn add(&mut self, other: &Profile) {
        self.detect += other.detect;
        self.prepare += other.prepare;
        self.integrate += other.integrate;
        self.rods += other.rods;
        self.joints += other.joints;
        self.contacts += other.contacts;
        self.commit += other.commit;
        self.velocity_pass += other.velocity_pass;
        self.health += other.health;
        self.sleep += other.sleep;
        self.step += other.step;
    }
}

/// Seconds since `*since`, which is moved to now: consecutive laps time consecutive phases.
#[inline]
pub fn lap(since: &mut Instant) -> f64 {
    let now = Instant::now();
    let seconds = (now - *since).as_secs_f64();
    *since = now;
    seconds
}
