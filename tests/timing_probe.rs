use rodlab::scene::{Overrides, Scene};
use std::time::Instant;

#[test]
fn timing_probe() {
    let path = format!("{}/scenes/ragdoll_rain.toml", env!("CARGO_MANIFEST_DIR"));
    let scene = Scene::load_with(&path, None, &Overrides::default()).unwrap();
    let mut best = f64::INFINITY;
    let mut profiles = Vec::new();
    for _ in 0..3 {
        let mut lab = scene.build().unwrap();
        let t = Instant::now();
        let mut sum = [0.0f64; 12];
        for _ in 0..120 {
            lab.step().unwrap();
            let p = &lab.world.solver.profile;
            for (i, (_, v)) in p.phases().iter().enumerate() {
                sum[i] += v;
            }
        }
        best = best.min(t.elapsed().as_secs_f64());
        profiles.push(sum.map(|v| (v * 1000.0 / 120.0 * 1000.0).round() / 1000.0));
    }
    println!(
        "rain 120 frames best {best:.3} s; {:?}",
        profiles.last().unwrap()
    );
}
