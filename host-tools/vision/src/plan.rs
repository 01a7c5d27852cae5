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
