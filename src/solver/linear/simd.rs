//! CPU feature dispatch for the hot kernels: a kernel runs in a build for AVX2 where the CPU
//! has it (three-operand instructions and 256-bit vectors: fewer instructions for the same
//! arithmetic), and in the baseline x86-64 build otherwise. The results are the same bit for
//! bit: no fused multiply-add is enabled, and Rust never reorders floating-point operations.
//! Code that needs AVX2 takes an `Avx2`, which only the CPU check makes.

/// Proof that the CPU runs AVX2: made only by [`Avx2::detect`], after the CPU check, so that a
/// function taking one may use AVX2 instructions safely.
#[derive(Clone, Copy, Debug)]
pub struct Avx2(());

impl Avx2 {
    /// The proof, where the CPU has AVX2 (detected once, then cached by std).
    #[inline(always)]
    pub fn detect() -> Option<Avx2> {
        #[cfg(target_arch = "x86_64")]
        if std::arch::is_x86_feature_detected!("avx2") {
            return Some(Avx2(()));
        }
        None
    }

    /// Run `kernel` compiled for AVX2. The kernel must be an `#[inline(always)]` closure, so
    /// that its body is compiled into the AVX2 instance.
    #[inline(always)]
    pub fn run<R>(self, kernel: impl FnOnce() -> R) -> R {
        #[cfg(target_arch = "x86_64")]
        {
            // SAFETY: an `Avx2` exists only where the CPU has AVX2 (`detect`).
            unsafe { with_avx2(kernel) }
        }
        #[cfg(not(target_arch = "x86_64"))]
        kernel()
    }
}

/// `kernel`, compiled for AVX2.
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2")]
unsafe fn with_avx2<R>(kernel: impl FnOnce() -> R) -> R {
    kernel()
}

/// Run `kernel` in the AVX2 build where the CPU has AVX2, in the baseline build otherwise.
/// The kernel must be an `#[inline(always)]` closure.
#[inline(always)]
pub(crate) fn dispatch<R>(kernel: impl FnOnce() -> R) -> R {
    dispatch_wide(
        #[inline(always)]
        |_| kernel(),
    )
}

/// `dispatch` for a kernel with a path of its own for AVX2: it gets the proof where it runs in
/// the AVX2 build, so that it may call AVX2 intrinsics.
#[inline(always)]
pub(crate) fn dispatch_wide<R>(kernel: impl FnOnce(Option<Avx2>) -> R) -> R {
    match Avx2::detect() {
        Some(cpu) => cpu.run(
            #[inline(always)]
            || kernel(Some(cpu)),
        ),
        None => kernel(None),
    }
}
