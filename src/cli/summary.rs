//! The run summary printed after a run: residuals, penetration, sleep, and the step's
//! phases.

use crate::scene::Scene;
use crate::sim::RunReport;

/// Prints the summary of a finished run of `scene` named `name`: frames, speed, energy and
/// state hash, the residuals, penetration, sleep and phase times.
pub fn print_summary(name: &str, scene: &Scene, report: &RunReport) {
    report!(
        "{name}: {} frames, dt {:.4} s, {} substep(s) x {} iterations{}, {} solver{} on {} \
         thread(s), {:.0} steps/s (stepping only), energy {:.1} J -> {:.1} J, state hash {:016x}",
        report.frames,
        scene.def.dt,
        scene.def.substeps,
        scene.def.iterations,
        match scene.def.contact_extra_sweeps {
            0 => String::new(),
            n => format!(" + {n} contact sweeps"),
        },
        scene.def.solver,
        match scene.def.solver {
            crate::world::SolverKind::Simd => {
                format!(" ({} lanes)", crate::lanes::LaneWidth::detect().lanes())
            }
            crate::world::SolverKind::Scalar => String::new(),
        },
        rayon::current_num_threads(),
        report.steps_per_second(),
        report.initial_energy,
        report.final_energy,
        report.state_hash
    );
    if report.ragdolls.len() > 4 {
        let frames = report.total_dislocation_cm.len().max(1) as f32;
        let mean = report.total_dislocation_cm.iter().sum::<f32>() / frames;
        let angular: f64 = report
            .ragdolls
            .iter()
            .map(|r| r.summary.mean_angular_rad())
            .sum();
        report!(
            "  {} ragdolls: total dislocation {mean:.3} cm and angular violation {angular:.4} rad, means over frames",
            report.ragdolls.len()
        );
        print_penetration(report);
        print_sleep(scene, report);
        print_profile(report);
        return;
    }
    report!(
        "  {:<14} {:<7} {:>14} {:>13} {:>15} {:>14} {:>18}",
        "ragdoll",
        "spine",
        "mean disl. cm",
        "max disl. cm",
        "mean ang. rad",
        "max ang. rad",
        "mean pose dev. cm"
    );
    for r in &report.ragdolls {
        report!(
            "  {:<14} {:<7} {:>14.4} {:>13.4} {:>15.5} {:>14.5} {:>18.4}",
            r.name,
            r.spine.map_or("group".to_string(), |s| s.to_string()),
            r.summary.mean_dislocation_cm(),
            r.summary.dislocation_max,
            r.summary.mean_angular_rad(),
            r.summary.angular_max,
            r.summary.mean_pose_deviation_cm()
        );
    }
    if scene.def.contacts {
        print_penetration(report);
    }
    print_sleep(scene, report);
    print_profile(report);
    for (i, rod) in report.final_rods.iter().enumerate() {
        report!(
            "  rod {i}: final psi {:.3} rad, tau {:.3} rad, length violation {:.4} cm, curve violation {:.5} rad",
            rod.psi,
            rod.tau,
            100.0 * rod.length_error,
            rod.curve_error
        );
    }
}

/// The step's phases, mean per frame (ms), the ones that took any time.
fn print_profile(report: &RunReport) {
    let frames = report.total_dislocation_cm.len().max(1) as f64; // frames stepped
    let phases: Vec<String> = (report.profile.phases().iter())
        .filter(|(_, s)| *s > 0.0)
        .map(|(name, s)| format!("{name} {:.3}", 1e3 * s / frames))
        .collect();
    if !phases.is_empty() {
        report!("  step profile, ms per frame: {}", phases.join(", "));
    }
}

/// The deepest penetration at the solver's contact points and the deepest overlap found afresh
/// on the final poses, over the run: the second catches what the first misses when bodies
/// slide over each other within a frame.
fn print_penetration(report: &RunReport) {
    report!(
        "  deepest contact penetration: {:.3} cm at the contact points, {:.3} cm found afresh",
        report.max_penetration_cm,
        report.max_overlap_cm
    );
}

/// With sleeping on: the awake bodies at the end, and the first frame with none awake.
fn print_sleep(scene: &Scene, report: &RunReport) {
    if !scene.def.sleep {
        return;
    }
    let last = report.awake_bodies.last().copied().unwrap_or(0);
    let all_asleep = report.awake_bodies.iter().position(|&n| n == 0);
    report!(
        "  sleeping: {last} dynamic bodies awake at the end{}",
        all_asleep.map_or(String::new(), |f| format!(
            "; all asleep from frame {}",
            f + 1
        ))
    );
    print_restless(report);
}

/// The bodies that keep their islands awake at the end, fastest first (at most five named).
fn print_restless(report: &RunReport) {
    const NAMED: usize = 5;
    let Some((name, fastest)) = report.restless.first() else {
        return;
    };
    report!(
        "  still moving (fastest surface point >= {} m/s): {} bodies; fastest {name} {:.3} m/s",
        crate::sleep::SLEEP_SPEED,
        report.restless.len(),
        fastest.point_speed
    );
    for (name, r) in report.restless.iter().take(NAMED) {
        report!(
            "    {name}: point {:.3} m/s, centre {:.3} m/s, spin {:.2} rad/s about its axis and {:.2} across",
            r.point_speed, r.centre_speed, r.axial_spin, r.cross_spin
        );
    }
}
