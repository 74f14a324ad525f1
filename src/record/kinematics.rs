//! The kinematics comparison (Fig. 6) drawn: the end loci, the spines at each bend, the gaps.

use rerun::RecordingStream;

use crate::scene::Scene;

/// Records the kinematics comparison (Fig. 6): the three end loci as static line strips, and per
/// frame the three spines at one bend with the end gaps. Returns the largest gaps (m) of the
/// equal and the unequal chain from the rod.
pub fn record_kinematics(rec: &RecordingStream, scene: &Scene) -> anyhow::Result<(f32, f32)> {
    use crate::kinematics::{chain_points, equal_weights, rod_points};
    let k = scene.def.kinematics.as_ref().expect("a kinematics scene");
    rec.set_log_time_enabled(false);
    rec.log_static("world", &rerun::ViewCoordinates::RIGHT_HAND_Y_UP())?;
    let text = format!("# {}\n\n```toml\n{}\n```\n", scene.name(), scene.text);
    rec.log_static("scene", &rerun::TextDocument::from_markdown(text))?;
    let total: f32 = k.unequal.iter().sum();
    let unequal: Vec<f32> = k.unequal.iter().map(|w| w / total).collect();
    let equal = equal_weights(k.joints);
    let max_bend = k.max_bend.to_radians();
    let frames = scene.def.frames.max(2) as usize;
    let bend = |i: usize| -max_bend + 2.0 * max_bend * i as f32 / (frames - 1) as f32;
    let spines: [(&str, rerun::Color); 3] = [
        ("equal_chain", rerun::Color::from_rgb(60, 110, 220)),
        ("unequal_chain", rerun::Color::from_rgb(60, 170, 90)),
        ("rod", rerun::Color::from_rgb(220, 60, 50)),
    ];
    let shape = |name: &str, psi: f32| match name {
        "equal_chain" => chain_points(k.length, psi, &equal),
        "unequal_chain" => chain_points(k.length, psi, &unequal),
        _ => rod_points(k.length, psi, 32),
    };
    for (name, color) in spines {
        let locus: Vec<[f32; 3]> = (0..frames)
            .map(|i| shape(name, bend(i)).last().unwrap().to_array())
            .collect();
        rec.log_static(
            format!("world/locus/{name}"),
            &rerun::LineStrips3D::new([locus])
                .with_colors([color])
                .with_radii([0.002]),
        )?;
    }
    let mut gaps = (0.0f32, 0.0f32);
    for i in 0..frames {
        let psi = bend(i);
        rec.set_time_sequence("frame", i as i64);
        rec.set_duration_secs("sim_time", i as f64 * scene.def.dt as f64);
        let rod_end = *shape("rod", psi).last().unwrap();
        for (name, color) in spines {
            let points = shape(name, psi);
            rec.log(
                format!("world/spine/{name}"),
                &rerun::LineStrips3D::new([points.iter().map(|p| p.to_array())])
                    .with_colors([color])
                    .with_radii([0.006]),
            )?;
            if name != "rod" {
                let gap = (*points.last().unwrap() - rod_end).length();
                if name == "equal_chain" {
                    gaps.0 = gaps.0.max(gap);
                } else {
                    gaps.1 = gaps.1.max(gap);
                }
                rec.log(
                    format!("metrics/end_gap_cm/{name}"),
                    &rerun::Scalars::single(100.0 * gap as f64),
                )?;
            }
        }
        rec.log("metrics/bend_rad", &rerun::Scalars::single(psi as f64))?;
    }
    rec.flush_blocking()?;
    Ok(gaps)
}
