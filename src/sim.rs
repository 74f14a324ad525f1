//! The run loop shared by the CLI, tests and benchmarks: step, measure, hand each frame to an
//! [`Observer`] (the recorder, a test, or nothing). No Rerun here.

use crate::lab::Lab;
use crate::metrics::{FrameMetrics, Summary};
use crate::ragdoll::SpineKind;
pub use crate::scene::Overrides;
use crate::world::SimulationError;

/// Receives the lab after every frame.
pub trait Observer {
    /// Called once before the first step, with the initial state as frame 0.
    fn begin(&mut self, _lab: &Lab, _metrics: &FrameMetrics) -> anyhow::Result<()> {
        Ok(())
    }
    /// Called after every frame's step and measure.
    fn frame(&mut self, lab: &Lab, metrics: &FrameMetrics) -> anyhow::Result<()>;
    /// Called when the simulation fails, after the last good frame was observed.
    fn failed(&mut self, _lab: &Lab, _error: &SimulationError) {}
    /// Asked after every frame: true ends the run there, as a whole run (its report covers
    /// the frames done).
    fn stop_requested(&self) -> bool {
        false
    }
}

/// An observer that ignores everything.
pub struct NoObserver;

impl Observer for NoObserver {
    fn frame(&mut self, _: &Lab, _: &FrameMetrics) -> anyhow::Result<()> {
        Ok(())
    }
}

impl<F: FnMut(&Lab, &FrameMetrics)> Observer for F {
    fn frame(&mut self, lab: &Lab, metrics: &FrameMetrics) -> anyhow::Result<()> {
        self(lab, metrics);
        Ok(())
    }
}

/// Residual statistics of one ragdoll over a run.
#[derive(Clone, Debug)]
pub struct RagdollReport {
    /// The ragdoll's name.
    pub name: String,
    /// The ragdoll's spine kind; `None` for a plain group.
    pub spine: Option<SpineKind>,
    /// Residual statistics over the frames stepped (the start, frame 0, excluded).
    pub summary: Summary,
}

/// What a run measured: residual statistics, energies, timings and the final state.
#[derive(Clone, Debug)]
pub struct RunReport {
    /// Frames stepped (fewer than asked if the observer stopped the run).
    pub frames: u32,
    /// Per ragdoll, in `lab.ragdolls` order.
    pub ragdolls: Vec<RagdollReport>,
    /// Total energy (J) before the first step.
    pub initial_energy: f32,
    /// Total energy (J) after the last frame.
    pub final_energy: f32,
    /// Final state of every rod, in constraint order.
    pub final_rods: Vec<crate::constraint::RodState>,
    /// Per frame, the dislocation (cm) summed over all ragdolls.
    pub total_dislocation_cm: Vec<f32>,
    /// Deepest contact penetration over the run (cm).
    pub max_penetration_cm: f32,
    /// Deepest overlap of the shapes over the run (cm), found afresh on each frame's final
    /// poses ([`FrameMetrics::max_overlap_cm`]).
    pub max_overlap_cm: f32,
    /// Wall time (s) spent in `World::step` alone: no measuring, no observer (recording).
    pub step_seconds: f64,
    /// Per frame, the dynamic bodies awake after it (all of them unless sleeping is on).
    pub awake_bodies: Vec<u32>,
    /// The steps' phases, summed over the run (see [`crate::solver::Profile`]).
    pub profile: crate::solver::Profile,
    /// After the last frame, the awake bodies too fast to fall asleep, fastest first, with
    /// their names ([`crate::sleep::restless_bodies`]).
    pub restless: Vec<(String, crate::sleep::Restless)>,
    /// [`crate::world::World::state_hash`] after the last frame.
    pub state_hash: u64,
}

impl RunReport {
    /// Frames stepped per second of wall time spent stepping (0 when nothing was stepped).
    pub fn steps_per_second(&self) -> f64 {
        match self.step_seconds > 0.0 {
            true => self.total_dislocation_cm.len() as f64 / self.step_seconds,
            false => 0.0,
        }
    }
}

/// Steps `lab` for `frames` frames. Residual statistics cover frames 1..=frames.
pub fn run(lab: &mut Lab, frames: u32, observer: &mut dyn Observer) -> anyhow::Result<RunReport> {
    let mut metrics = FrameMetrics::default();
    metrics.measure(lab);
    let initial_energy = metrics.total_energy();
    let mut ragdolls: Vec<RagdollReport> = lab
        .ragdolls
        .iter()
        .map(|r| RagdollReport {
            name: r.name.clone(),
            spine: r.spine,
            summary: Summary::default(),
        })
        .collect();
    observer.begin(lab, &metrics)?;
    let mut total_dislocation_cm = Vec::with_capacity(frames as usize);
    let mut max_penetration_cm = 0.0f32;
    let mut max_overlap_cm = 0.0f32;
    let mut step_seconds = 0.0f64;
    let mut awake_bodies = Vec::with_capacity(frames as usize);
    let mut profile = crate::solver::Profile::default();
    for _ in 0..frames {
        let started = std::time::Instant::now();
        let stepped = lab.step();
        step_seconds += started.elapsed().as_secs_f64();
        if let Err(error) = stepped {
            observer.failed(lab, &error);
            return Err(error.into());
        }
        metrics.measure(lab);
        total_dislocation_cm.push(metrics.totals().0);
        awake_bodies.push(lab.world.awake_bodies as u32);
        profile.add(&lab.world.solver.profile);
        max_penetration_cm = max_penetration_cm.max(metrics.max_penetration_cm);
        max_overlap_cm = max_overlap_cm.max(metrics.max_overlap_cm);
        for (report, residual) in ragdolls.iter_mut().zip(&metrics.ragdolls) {
            report.summary.add(*residual);
        }
        observer.frame(lab, &metrics)?;
        if observer.stop_requested() {
            break;
        }
    }
    Ok(RunReport {
        frames: total_dislocation_cm.len() as u32,
        ragdolls,
        initial_energy,
        final_energy: metrics.total_energy(),
        final_rods: metrics.rods,
        total_dislocation_cm,
        max_penetration_cm,
        max_overlap_cm,
        step_seconds,
        awake_bodies,
        profile,
        restless: (crate::sleep::restless_bodies(&lab.world.bodies).into_iter())
            .map(|r| (lab.world.body(r.body).name.clone(), r))
            .collect(),
        state_hash: lab.world.state_hash(),
    })
}
