//! Running a tract plan: the one place this crate's networks (camera and radar) call into
//! tract's kernels, and where it leaves the CPU as those kernels should have.
//!
//! tract's x86-64 matrix kernels (hand-written AVX2/FMA and AVX-512 assembly in tract-linalg)
//! return without `vzeroupper`, so the upper halves of the vector registers stay dirty on the
//! thread that ran them. Every legacy-SSE instruction that thread runs afterwards (all of our
//! x86-64 code: the DSP, the point cloud, IP-Basic) then pays for merging them: on this
//! project's 2-core host the map path per radar frame after one inference took about twice
//! as long (README, "the frame rate after the network"). [`run`] clears that state, as a
//! compiler does at the end of any function that used AVX; so does [`optimized`].

use tract_onnx::prelude::*;

/// A loaded, optimised, runnable tract model.
pub(crate) type Plan = Arc<TypedRunnableModel>;

/// `model` optimised into a runnable plan (optimising may evaluate constant parts with the
/// same kernels, so the state is cleared after it too).
///
/// # Errors
/// Whatever tract's optimisation returns.
pub(crate) fn optimized(model: InferenceModel) -> TractResult<Plan> {
    let plan = model.into_optimized().and_then(IntoRunnable::into_runnable);
    clear_upper();
    plan
}

/// Runs `plan` on `inputs`, then clears the vector registers' upper halves on this thread
/// (see the module docs). The outputs are tract's, unchanged.
///
/// # Errors
/// Whatever tract's run returns.
pub(crate) fn run(plan: &Plan, inputs: TVec<TValue>) -> TractResult<TVec<TValue>> {
    let out = plan.run(inputs);
    clear_upper();
    out
}

/// `vzeroupper` where the CPU has AVX; nothing elsewhere.
#[allow(unsafe_code)]
fn clear_upper() {
    #[cfg(target_arch = "x86_64")]
    if std::arch::is_x86_feature_detected!("avx") {
        // SAFETY: `zero_upper` needs AVX, which the CPU was just found to have. `vzeroupper`
        // zeroes only bits 128 and up of the vector registers, which hold no live value
        // across a call (the System V and Windows x64 ABIs make them caller-saved).
        unsafe { zero_upper() }
    }
}

#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx")]
fn zero_upper() {
    std::arch::x86_64::_mm256_zeroupper();
}

#[cfg(all(test, target_arch = "x86_64"))]
mod tests {
    use super::*;

    /// XINUSE (`xgetbv` with ECX = 1): which state components are not in their initial
    /// state. Bit 2 is the upper halves of YMM0–15, bit 6 of ZMM0–15. `None` where the CPU
    /// does not report it.
    #[allow(unsafe_code)]
    fn in_use() -> Option<u64> {
        #[target_feature(enable = "xsave")]
        unsafe fn xinuse() -> u64 {
            // SAFETY: the caller checked that the CPU reports XINUSE.
            unsafe { std::arch::x86_64::_xgetbv(1) }
        }
        // CPUID leaf 0xD, sub-leaf 1, EAX bit 2: XGETBV with ECX = 1 is supported.
        let leaf = std::arch::x86_64::__cpuid_count(0xd, 1);
        (std::arch::is_x86_feature_detected!("xsave") && leaf.eax & 4 != 0)
            // SAFETY: the CPU has XSAVE and reports XINUSE, both checked just before.
            .then(|| unsafe { xinuse() })
    }

    const UPPER: u64 = (1 << 2) | (1 << 6);

    /// The shipped small-board network, optimised, and an input of its size.
    fn network() -> (Plan, TVec<TValue>) {
        let path = concat!(env!("CARGO_MANIFEST_DIR"), "/models/radarhr.onnx");
        let model = onnx().model_for_path(path).expect(path);
        let input = Tensor::from_shape(&[1, 1, 80, 320], &vec![0.25f32; 80 * 320]).expect("size");
        (optimized(model).expect("model"), tvec!(input.into()))
    }

    #[test]
    fn run_leaves_the_upper_halves_clean() {
        let (plan, input) = network();
        let Some(before) = in_use() else {
            eprintln!("this CPU does not report XINUSE: nothing to check");
            return;
        };
        assert_eq!(before & UPPER, 0, "dirty before any run: {before:#x}");
        // tract alone leaves them dirty on a CPU whose kernels use them (the probe works)...
        let raw = plan.run(input.clone()).expect("run");
        let dirty = in_use().unwrap_or(0) & UPPER;
        clear_upper();
        // ...and `run` does not, with the same outputs.
        let cleared = run(&plan, input).expect("run");
        let after = in_use().unwrap_or(u64::MAX);
        if std::arch::is_x86_feature_detected!("avx2") {
            assert_ne!(
                dirty, 0,
                "tract's kernels did not dirty the registers: a weak probe"
            );
        }
        assert_eq!(after & UPPER, 0, "dirty after run: {after:#x}");
        let values = |out: &TVec<TValue>| {
            out[0]
                .try_as_plain_ram()
                .and_then(|v| v.as_slice::<f32>())
                .map(<[f32]>::to_vec)
                .expect("f32 output")
        };
        assert_eq!(values(&raw), values(&cleared));
    }
}
