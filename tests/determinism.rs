//! The same result on every machine (Box2D v3's `test_determinism.c`, Jolt's
//! `CROSS_PLATFORM_DETERMINISTIC`): each case's final state hash ([`World::state_hash`]: every
//! body's pose, velocities and sleep state, bit for bit) is a committed constant, asserted at
//! every lane width this CPU runs (4, 8, 16), on one thread and on two, with the scalar and
//! with the SIMD solver. A build for any x86-64 CPU, with any target features, must give these
//! constants; `.ci/run` runs this file again from a build for the CPU it runs on
//! (`-C target-cpu=native`).
//!
//! This test binary needs no recording: `cargo test --release --no-default-features --test
//! determinism` builds the physics alone.
//!
//! When a change to the physics changes a result on purpose, the failure prints every case's
//! new hash; the constants are then updated with the change.
//!
//! [`World::state_hash`]: rodlab::world::World::state_hash

use rodlab::lanes::LaneWidth;
use rodlab::ragdoll::SpineKind;
use rodlab::scene::{Overrides, Scene};
use rodlab::world::SolverKind;

/// One run whose final state is asserted.
struct Case {
    scene: &'static str,
    variant: Option<&'static str>,
    spine: Option<SpineKind>,
    solver: SolverKind,
    frames: u32,
    /// The final state hash.
    hash: u64,
}

impl Case {
    fn label(&self) -> String {
        let spine = self.spine.map(|s| format!(" {s:?}")).unwrap_or_default();
        let variant = self.variant.unwrap_or("paper");
        let solver = format!("{:?}", self.solver).to_lowercase();
        format!(
            "{} {variant}{spine} {solver}, {} frames",
            self.scene, self.frames
        )
    }

    /// The final state hash at `width` on `threads` threads.
    fn run(&self, width: LaneWidth, threads: usize) -> u64 {
        let path = format!("{}/scenes/{}.toml", env!("CARGO_MANIFEST_DIR"), self.scene);
        let overrides = Overrides {
            spine: self.spine,
            solver: Some(self.solver),
            ..Default::default()
        };
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .unwrap();
        pool.install(|| {
            let scene = Scene::load_with(&path, self.variant, &overrides).unwrap();
            let mut lab = scene.build().unwrap();
            lab.world.set_lane_width(width);
            for frame in 0..self.frames {
                let stepped = lab.step();
                assert!(
                    stepped.is_ok(),
                    "{} frame {frame}: {stepped:?}",
                    self.label()
                );
            }
            lab.world.state_hash()
        })
    }
}

const CASES: &[Case] = &[
    Case {
        scene: "passive_bending",
        variant: None,
        spine: None,
        solver: SolverKind::Scalar,
        frames: 360,
        hash: 0x78b0_969d_4dae_f94a,
    },
    Case {
        scene: "passive_bending",
        variant: None,
        spine: None,
        solver: SolverKind::Simd,
        frames: 360,
        hash: 0x0c5d_62c6_ac9e_ee63,
    },
    Case {
        scene: "controllability",
        variant: None,
        spine: None,
        solver: SolverKind::Scalar,
        frames: 300,
        hash: 0x1712_6a61_407b_76a8,
    },
    Case {
        scene: "controllability",
        variant: None,
        spine: None,
        solver: SolverKind::Simd,
        frames: 300,
        hash: 0xc347_9e82_008c_3048,
    },
    Case {
        scene: "ragdoll_drop",
        variant: None,
        spine: Some(SpineKind::Chain3),
        solver: SolverKind::Scalar,
        frames: 300,
        hash: 0x7e4f_deb8_ec2f_afd3,
    },
    Case {
        scene: "ragdoll_drop",
        variant: None,
        spine: Some(SpineKind::Rod),
        solver: SolverKind::Simd,
        frames: 300,
        hash: 0xa629_1537_59d2_da08,
    },
    Case {
        scene: "ragdoll_drop",
        variant: Some("game"),
        spine: Some(SpineKind::Chain3),
        solver: SolverKind::Simd,
        frames: 300,
        hash: 0x5bcf_dfd8_d2f5_5798,
    },
    Case {
        scene: "ragdoll_drop",
        variant: Some("game"),
        spine: Some(SpineKind::Rod),
        solver: SolverKind::Scalar,
        frames: 300,
        hash: 0x403d_9b6a_7e03_b7a8,
    },
    Case {
        scene: "ragdoll_drop",
        variant: Some("stacked"),
        spine: Some(SpineKind::Chain3),
        solver: SolverKind::Simd,
        frames: 150,
        hash: 0x8c02_b65a_efa6_59f0,
    },
    Case {
        scene: "ragdoll_drop",
        variant: Some("tight"),
        spine: Some(SpineKind::Rod),
        solver: SolverKind::Simd,
        frames: 150,
        hash: 0x0eba_ea99_f5c7_3e2e,
    },
    Case {
        scene: "ragdoll_rain",
        variant: None,
        spine: None,
        solver: SolverKind::Simd,
        frames: 60,
        hash: 0x6dc6_0084_c0da_8258,
    },
];

/// Every case's hash at every width this CPU runs and on one and two threads is its committed
/// constant.
#[test]
fn every_case_gives_its_committed_state_hash_at_every_width_and_thread_count() {
    let widths: Vec<LaneWidth> = LaneWidth::available().collect();
    let mut report = Vec::new();
    let mut wrong = 0;
    for case in CASES {
        for &width in &widths {
            for threads in [1, 2] {
                let started = std::time::Instant::now();
                let hash = case.run(width, threads);
                let ok = hash == case.hash;
                wrong += !ok as usize;
                report.push(format!(
                    "{} at {} lanes, {threads} thread(s): {hash:#018x}{} ({:.1} s)",
                    case.label(),
                    width.lanes(),
                    if ok {
                        String::new()
                    } else {
                        format!(" (committed: {:#018x})", case.hash)
                    },
                    started.elapsed().as_secs_f64()
                ));
            }
        }
    }
    println!("{}", report.join("\n"));
    assert_eq!(
        wrong,
        0,
        "{wrong} runs differ from their committed hash:\n{}",
        report.join("\n")
    );
}
