//! The machine a timing was taken on, named as precisely as the CPU reports it.

/// The CPU model, its family and model numbers, its widest vector instructions, the lane width
/// the SIMD solver runs, and the core count: a cloud VM reports "AMD EPYC" for CPUs of
/// different generations, whose SIMD kernels run at different speeds.
pub fn name() -> String {
    let cores = std::thread::available_parallelism().map_or(1, |n| n.get());
    let info = std::fs::read_to_string("/proc/cpuinfo").unwrap_or_default();
    let field = |name: &str| {
        info.lines()
            .find(|l| l.split(':').next().is_some_and(|k| k.trim() == name))
            .and_then(|l| l.split(':').nth(1))
            .map(|v| v.trim().to_string())
    };
    let model = field("model name").unwrap_or_else(|| std::env::consts::ARCH.to_string());
    let generation = match (field("cpu family"), field("model")) {
        (Some(family), Some(number)) => format!("family {family} model {number}, "),
        _ => String::new(),
    };
    let lanes = crate::lanes::LaneWidth::detect().lanes();
    format!(
        "{model} ({generation}{}, {lanes} lanes), {cores} cores",
        vector_instructions()
    )
}

/// The widest vector instruction set this CPU runs (probed on x86-64 only).
fn vector_instructions() -> &'static str {
    #[cfg(target_arch = "x86_64")]
    {
        if std::arch::is_x86_feature_detected!("avx512f") {
            return "AVX-512";
        }
        if std::arch::is_x86_feature_detected!("avx2") {
            return "AVX2";
        }
        "SSE2"
    }
    #[cfg(not(target_arch = "x86_64"))]
    "vector set not probed"
}
