//! The stability suite (`rodlab::stress`): its verdicts call a deliberately broken
//! configuration exploded and a calm one stable, by running them; a stiff rod spine
//! (alpha_b = alpha_t = 1) stays stable at dt = 1/30 s as the paper claims; the tables hold one
//! row per case and per run and parse back. Run with `--nocapture` to see the suite's table.

use std::time::Instant;

use rodlab::lab::Lab;
use rodlab::metrics::FrameMetrics;
use rodlab::sim::NoObserver;
use rodlab::stress::{
    run_case, run_suite, suite, table_csv, table_markdown, tripped, verdict, Case, Criteria,
    Measures, Method, Outcome, Scenario, Verdict, CSV_HEADER,
};

fn run(case: &Case, method: Method) -> Outcome {
    run_case(case, method, &mut NoObserver)
        .expect("NoObserver never fails")
        .expect("the case applies to every ragdoll method")
}

fn custom(scenario: Scenario, dt: f32, iterations: u32, seconds: f32) -> Case {
    Case {
        name: "custom",
        description: "",
        scenario,
        dt,
        iterations,
        seconds,
    }
}

fn suite_case(name: &str) -> Case {
    suite().into_iter().find(|c| c.name == name).unwrap()
}

/// A weight of 1000 forearm masses in the hand with one iteration at dt = 1/5 s: the arm
/// cannot hold it, flings (peak speeds 51 to 95 m/s against a 7 m/s reference, measured) and
/// comes apart (the world's separation bound may stop it first). With 10 000 forearm masses at
/// 60 Hz the world's own speed or separation bound stops the run.
/// A ragdoll hung by its head at rest, 60 Hz, 20 iterations, stays calm and is stable.
#[test]
fn verdicts_call_a_broken_configuration_exploded_and_a_calm_one_stable() {
    let broken = custom(Scenario::HeavyHand { mass_ratio: 1000.0 }, 0.2, 1, 4.0);
    let overloaded = custom(Scenario::HeavyHand { mass_ratio: 1e4 }, 1.0 / 60.0, 20, 4.0);
    let calm = custom(Scenario::Hanging { psi_deg: 0.0 }, 1.0 / 60.0, 20, 3.0);
    for method in Method::ALL {
        let o = run(&broken, method);
        let m = &o.measures;
        assert_eq!(o.verdict, Verdict::Exploded, "{method}: {m:?}");
        // flung past 5x the reference speed, or stopped first by the world's separation bound
        let came_apart = m
            .failed
            .as_deref()
            .is_some_and(|f| f.contains("came apart"));
        assert!(
            came_apart || m.peak_speed > 5.0 * m.speed_reference,
            "{method}: peak {} m/s against a reference of {} m/s, failure {:?}",
            m.peak_speed,
            m.speed_reference,
            m.failed
        );

        let o = run(&overloaded, method);
        assert_eq!(o.verdict, Verdict::Exploded, "{method}: {:?}", o.measures);
        let failure = (o.measures.failed.as_deref()).expect("the world's health check trips");
        assert!(
            failure.contains("exploded") || failure.contains("came apart"),
            "{method}: {failure}"
        );
        assert!(o.measures.frames_run < o.measures.frames);

        let o = run(&calm, method);
        let m = &o.measures;
        assert_eq!(o.verdict, Verdict::Stable, "{method}: {m:?}");
        // at rest: no energy made, nothing faster than 5 cm/s at the end, joints closed
        assert_eq!(m.energy_growth, 0.0, "{method}");
        assert!(m.final_speed < 0.05, "{method}: {} m/s", m.final_speed);
        assert!(
            m.max_residual_cm < 0.5,
            "{method}: {} cm",
            m.max_residual_cm
        );
    }
}

/// The paper (§1, §5): soft constraints keep stiff rods stable at long time steps. With
/// alpha_b = alpha_t = 1 the rod holds the 30-degree lean: the bend psi stays within 0.015 rad
/// at dt = 1/30 s and 0.06 rad at dt = 1/15 s (measured 0.015 and 0.050), its length within
/// 1 mm and 2 mm (measured 0.34 and 1.2 mm). The observer passed to `run_case` sees every frame.
#[test]
fn stiff_rod_spine_is_stable_at_long_time_steps() {
    let bounds = [
        ("stiff_spine_dt_1_30", 0.02, 0.1),
        ("stiff_spine_dt_1_15", 0.06, 0.2),
    ];
    for (name, max_psi, max_residual_cm) in bounds {
        let case = suite_case(name);
        let (mut frames, mut largest_psi) = (0, 0.0f32);
        let mut observer = |_: &Lab, metrics: &FrameMetrics| {
            frames += 1;
            largest_psi = largest_psi.max(metrics.rods[0].psi);
        };
        let o = run_case(&case, Method::Rod, &mut observer)
            .unwrap()
            .unwrap();
        let m = &o.measures;
        assert_eq!(o.verdict, Verdict::Stable, "{name}: {m:?}");
        assert_eq!(frames, case.frames());
        assert!(
            largest_psi < max_psi,
            "{name}: psi reached {largest_psi} rad"
        );
        assert!(
            m.max_residual_cm < max_residual_cm,
            "{name}: {} cm",
            m.max_residual_cm
        );
        assert_eq!(m.energy_growth, 0.0, "{name}");
    }
}

/// The suite runs whole; the markdown table has one row per case and one column per method,
/// every cell a verdict (or `-` where the case does not apply); the CSV has one row per run and
/// parses back to the same verdicts and numbers. Prints both tables and the time taken.
#[test]
fn tables_have_one_row_per_case_and_per_run_and_parse_back() {
    let start = Instant::now();
    let outcomes = run_suite();
    let seconds = start.elapsed().as_secs_f64();
    let cases = suite();
    let markdown = table_markdown(&outcomes);
    let csv = table_csv(&outcomes);
    println!(
        "{markdown}\n{csv}\nsuite: {} runs in {seconds:.2} s",
        outcomes.len()
    );

    // every case runs for every ragdoll method; chains skip `single`
    let chains = cases
        .iter()
        .filter(|c| matches!(c.scenario, Scenario::Chain { .. }))
        .count();
    assert_eq!(outcomes.len(), 4 * cases.len() - chains);

    let rows: Vec<Vec<&str>> = markdown
        .lines()
        .map(|line| line.trim_matches('|').split('|').map(str::trim).collect())
        .collect();
    assert_eq!(
        rows.len(),
        2 + cases.len(),
        "header, rule, one row per case"
    );
    let header: Vec<String> = Method::ALL.iter().map(|m| m.to_string()).collect();
    assert_eq!(
        rows[0][1..],
        header.iter().map(String::as_str).collect::<Vec<_>>()
    );
    for (row, case) in rows[2..].iter().zip(&cases) {
        assert_eq!(row.len(), 1 + Method::ALL.len());
        assert_eq!(row[0], case.name);
        for (cell, method) in row[1..].iter().zip(Method::ALL) {
            match outcomes
                .iter()
                .find(|o| o.case == case.name && o.method == method)
            {
                Some(o) => assert!(
                    cell.starts_with(&o.verdict.to_string()),
                    "{} {method}: cell {cell:?}",
                    case.name
                ),
                None => assert_eq!(*cell, "-"),
            }
        }
    }

    let rows = rodlab::csv_table::read(&csv, CSV_HEADER).expect("the stress table reads back");
    let columns: Vec<&str> = CSV_HEADER.split(',').collect();
    let column = |name: &str| columns.iter().position(|c| *c == name).unwrap();
    assert_eq!(rows.len(), outcomes.len(), "one row per run");
    for ((line, fields), o) in rows.iter().zip(&outcomes) {
        assert_eq!(fields.len(), columns.len(), "line {line}");
        assert_eq!(&fields[column("case")], o.case);
        assert_eq!(fields[column("method")], o.method.to_string());
        assert_eq!(fields[column("verdict")], o.verdict.to_string());
        let number = |name: &str| fields[column(name)].parse::<f32>().unwrap();
        assert_eq!(number("frames_run") as u32, o.measures.frames_run);
        assert!((number("peak_speed_m_s") - o.measures.peak_speed).abs() < 1e-3);
        assert!((number("mean_residual_cm") - o.measures.mean_residual_cm).abs() < 1e-4);
        let failed = o.measures.failed.as_deref().unwrap_or("");
        assert_eq!(&fields[column("failed")], failed, "line {line}");
    }

    // the paper's scene at its own settings is stable for every method
    for o in outcomes.iter().filter(|o| o.case == "baseline") {
        assert_eq!(o.verdict, Verdict::Stable, "baseline {}", o.method);
    }
    assert!(seconds < 60.0, "the suite took {seconds} s");
}

/// Runs are deterministic: the same case twice gives the same measures (so a failing run's
/// recording shows the failure the table reports).
#[test]
fn runs_repeat_exactly() {
    let case = suite_case("chain_40");
    for method in [Method::Chain3Cheap, Method::Rod] {
        assert_eq!(run(&case, method).measures, run(&case, method).measures);
    }
}

fn calm_measures() -> Measures {
    Measures {
        frames_run: 240,
        frames: 240,
        speed_reference: 7.0,
        peak_speed: 5.0,
        final_speed: 0.01,
        settles: true,
        max_residual_cm: 1.0,
        mean_residual_cm: 0.5,
        mean_angular_rad: 0.1,
        shake: 0.01,
        ..Measures::default()
    }
}

/// Each threshold on its own, just below and just above, with hand-made measures.
#[test]
fn verdict_thresholds() {
    let c = Criteria::default();
    assert_eq!(verdict(&calm_measures(), &c), Verdict::Stable);
    assert_eq!(tripped(&calm_measures(), &c), None);
    type Edit = fn(&mut Measures, f32);
    let cases: [(&str, f32, Verdict, Edit); 8] = [
        (
            "energy kept",
            c.exploded_final_energy_growth,
            Verdict::Exploded,
            |m, x| {
                m.final_energy_growth = x;
                m.energy_growth = x;
            },
        ),
        (
            "peak speed",
            c.exploded_speed_factor * 7.0,
            Verdict::Exploded,
            |m, x| m.peak_speed = x,
        ),
        ("torn", c.exploded_residual_cm, Verdict::Exploded, |m, x| {
            m.mean_residual_cm = x;
            m.max_residual_cm = x;
        }),
        (
            "energy kept",
            c.jitter_final_energy_growth,
            Verdict::Jittering,
            |m, x| {
                m.final_energy_growth = x;
                m.energy_growth = x;
            },
        ),
        (
            "energy pop",
            c.jitter_energy_growth,
            Verdict::Jittering,
            |m, x| m.energy_growth = x,
        ),
        (
            "residual",
            c.jitter_residual_cm,
            Verdict::Jittering,
            |m, x| {
                m.mean_residual_cm = x;
                m.max_residual_cm = x;
            },
        ),
        (
            "end speed",
            c.jitter_final_speed,
            Verdict::Jittering,
            |m, x| m.final_speed = x,
        ),
        ("shake", c.jitter_shake, Verdict::Jittering, |m, x| {
            m.shake = x
        }),
    ];
    for (what, threshold, expected, edit) in cases {
        let mut below = calm_measures();
        edit(&mut below, 0.99 * threshold);
        let mut above = calm_measures();
        edit(&mut above, 1.01 * threshold);
        // the next criterion down may catch "below" (a kept energy is also a pop), never as
        // severe a verdict as `expected` unless it is the same class
        assert!(verdict(&below, &c) <= expected, "{what} below: {below:?}");
        assert_eq!(verdict(&above, &c), expected, "{what} above: {above:?}");
    }
    // the end speed only counts in scenes that should come to rest
    let mut swinging = calm_measures();
    swinging.settles = false;
    swinging.final_speed = 3.0;
    assert_eq!(verdict(&swinging, &c), Verdict::Stable);
    // a failure or a NaN is an explosion whatever else was measured
    let mut failed = calm_measures();
    failed.failed = Some("frame 12: body \"b\" has a non-finite pose".into());
    assert_eq!(
        tripped(&failed, &c),
        Some((Verdict::Exploded, "frame 12".into()))
    );
    let mut nan = calm_measures();
    nan.shake = f32::NAN;
    assert_eq!(verdict(&nan, &c), Verdict::Exploded);
}

/// The stress table quotes a failure message instead of rewriting its commas.
#[test]
fn the_stress_table_keeps_a_failure_message_with_commas() {
    let message = "frame 12: body \"drop0/head\", constraint \"neck\", 509 rad/s";
    let outcome = rodlab::stress::Outcome {
        case: "pile, tight",
        method: rodlab::stress::Method::Rod,
        verdict: rodlab::stress::Verdict::Exploded,
        measures: rodlab::stress::Measures {
            failed: Some(message.to_string()),
            ..Default::default()
        },
    };
    let text = rodlab::stress::table_csv(&[outcome]);
    let rows = rodlab::csv_table::read(&text, rodlab::stress::CSV_HEADER).unwrap();
    let record = &rows[0].1;
    assert_eq!(&record[0], "pile, tight");
    assert_eq!(&record[record.len() - 1], message);
}
