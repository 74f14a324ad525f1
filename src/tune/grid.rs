//! The tuning grid's run and summary: every copy stepped in lockstep, each copy's row (settled
//! values, overshoot, settling times), and the summary as CSV and as a chart.

use rayon::prelude::*;

use super::{
    build_copy, copies, settled, settling_time, Copy, RodSetting, Softness, Trace, TuneConfig,
    SETTLED_WINDOW_S,
};
use crate::chart::{Chart, Series};
use crate::lab::Lab;
use crate::scene::Scene;

/// A copy's row of the summary.
#[derive(Clone, Debug, PartialEq)]
pub struct TuneRow {
    /// The copy this row sums up.
    pub copy: Copy,
    /// Substeps per frame (the scene's).
    pub substeps: u32,
    /// Settled bend psi (rad): the mean over the last [`SETTLED_WINDOW_S`].
    pub final_psi: f32,
    /// Settled twist tau (rad): the mean over the last [`SETTLED_WINDOW_S`].
    pub final_tau: f32,
    /// Largest psi above the final one (rad).
    pub psi_overshoot: f32,
    /// Time (s) from which psi stays within [`SETTLING_BAND`](super::SETTLING_BAND) of its
    /// settled value; infinite if never.
    pub psi_settling_s: f32,
    /// Time (s) from which tau stays within [`SETTLING_BAND`](super::SETTLING_BAND) of its
    /// settled value; infinite if never.
    pub tau_settling_s: f32,
    /// Mean over the frames of the ragdoll's summed dislocation (cm).
    pub mean_dislocation_cm: f32,
    /// Why the copy stopped, with the frame, if it failed.
    pub failed: Option<String>,
}

fn summarize(copy: &Copy, trace: &Trace, dt: f32, substeps: u32) -> TuneRow {
    let window = (SETTLED_WINDOW_S / dt).round() as usize;
    let final_psi = settled(&trace.psi, window);
    let final_tau = settled(&trace.tau, window);
    let peak = trace.psi.iter().copied().fold(f32::NEG_INFINITY, f32::max);
    let n = trace.dislocation_cm.len().max(1) as f32;
    TuneRow {
        copy: copy.clone(),
        substeps,
        final_psi,
        final_tau,
        psi_overshoot: (peak - final_psi).max(0.0),
        psi_settling_s: settling_time(&trace.psi, final_psi, dt),
        tau_settling_s: settling_time(&trace.tau, final_tau, dt),
        mean_dislocation_cm: trace.dislocation_cm.iter().sum::<f32>() / n,
        failed: trace.failed.clone(),
    }
}

/// Each frame of [`run_grid`]: the frame number, and every running copy's lab (`None` once a
/// copy has failed).
pub type FrameObserver<'a> = dyn FnMut(u64, &[Option<&Lab>]) -> anyhow::Result<()> + 'a;

/// Builds this shard's copies and steps them in lockstep (in parallel across copies), calling
/// `observer` after the initial state and every frame. A copy that fails stops there, and its
/// row says why; the others go on.
pub fn run_grid(
    scene: &Scene,
    config: &TuneConfig,
    observer: &mut FrameObserver<'_>,
) -> anyhow::Result<(Vec<TuneRow>, Vec<Trace>)> {
    let mine: Vec<Copy> = copies(config, scene.def.iterations)
        .into_iter()
        .filter(|c| config.shard.takes(c.index))
        .collect();
    let mut labs = Vec::with_capacity(mine.len());
    for copy in &mine {
        let setting = RodSetting {
            bend: copy.bend,
            twist: copy.twist,
            bend_damping: config.bend_damping,
            twist_damping: config.twist_damping,
        };
        labs.push(build_copy(
            scene,
            setting,
            copy.iterations,
            config.frames,
            copy.offset,
            config.twist_push,
        )?);
    }
    let frames = config.frames.unwrap_or(scene.def.frames);
    let mut traces = vec![Trace::default(); mine.len()];
    let observe = |labs: &[Lab], traces: &[Trace], frame: u64, observer: &mut FrameObserver<'_>| {
        let running: Vec<Option<&Lab>> = (labs.iter().zip(traces))
            .map(|(lab, trace)| trace.failed.is_none().then_some(lab))
            .collect();
        observer(frame, &running)
    };
    observe(&labs, &traces, 0, observer)?;
    for frame in 1..=frames as u64 {
        labs.par_iter_mut()
            .zip(traces.par_iter_mut())
            .filter(|(_, trace)| trace.failed.is_none())
            .for_each(|(lab, trace)| match lab.step() {
                Ok(()) => trace.record(lab),
                Err(e) => trace.failed = Some(format!("frame {frame}: {e}")),
            });
        observe(&labs, &traces, frame, observer)?;
    }
    let (dt, substeps) = (scene.def.dt, scene.def.substeps);
    let rows = (mine.iter().zip(&traces))
        .map(|(copy, trace)| summarize(copy, trace, dt, substeps))
        .collect();
    Ok((rows, traces))
}

/// Column names of [`to_csv`].
pub const CSV_HEADER: &str = "index,bend_kind,bend,twist_kind,twist,iterations,substeps,\
final_psi_rad,final_tau_rad,psi_overshoot_rad,psi_settling_s,tau_settling_s,mean_dislocation_cm,failed";

/// The summary as CSV, one row per copy (the failure message quoted where it needs it).
pub fn to_csv(rows: &[TuneRow]) -> String {
    crate::csv_table::to_text(
        CSV_HEADER,
        rows.iter().map(|r| {
            let (bend_kind, bend) = r.copy.bend.columns();
            let (twist_kind, twist) = r.copy.twist.columns();
            vec![
                r.copy.index.to_string(),
                bend_kind.to_string(),
                bend.to_string(),
                twist_kind.to_string(),
                twist.to_string(),
                r.copy.iterations.to_string(),
                r.substeps.to_string(),
                format!("{:.5}", r.final_psi),
                format!("{:.5}", r.final_tau),
                format!("{:.5}", r.psi_overshoot),
                format!("{:.3}", r.psi_settling_s),
                format!("{:.3}", r.tau_settling_s),
                format!("{:.5}", r.mean_dislocation_cm),
                r.failed.clone().unwrap_or_default(),
            ]
        }),
    )
}

/// The summary chart: the settled bend against the bend setting, one line per twist setting
/// and iteration count (log x axis when every setting is positive).
pub fn chart(scene: &str, rows: &[TuneRow]) -> Chart {
    let mut series: Vec<Series> = Vec::new();
    for r in rows.iter().filter(|r| r.failed.is_none()) {
        let label = format!("{}, {} it", r.copy.twist.label("twist"), r.copy.iterations);
        let x = r.copy.bend.columns().1 as f64;
        let point = (x, r.final_psi as f64);
        match series.iter_mut().find(|s| s.label == label) {
            Some(s) => s.points.push(point),
            None => series.push(Series {
                label,
                points: vec![point],
            }),
        }
    }
    for s in &mut series {
        s.points.sort_by(|a, b| a.0.total_cmp(&b.0));
    }
    let setting = rows.first().map_or(Softness::Alpha(0.0), |r| r.copy.bend);
    let x_label = match setting {
        Softness::Alpha(_) => "alpha_b (fraction of psi removed per iteration)",
        Softness::Stiffness(_) => "bend stiffness (N m/rad)",
    };
    Chart {
        title: format!("{scene}: the bend each setting ends at"),
        x_label: x_label.into(),
        y_label: format!("psi, mean of the last {SETTLED_WINDOW_S} s (rad)"),
        x_log: rows.iter().all(|r| r.copy.bend.columns().1 > 0.0),
        y_log: false,
        series,
    }
}
