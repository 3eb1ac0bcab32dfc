//! CPU feature dispatch for the hot kernels: a kernel runs in a build for AVX2 where the CPU
//! has it (three-operand instructions and 256-bit vectors: fewer instructions for the same
//! arithmetic), and in the baseline x86-64 build otherwise. The results are the same bit for
//! bit: no fused multiply-add is enabled, and Rust never reorders floating-point operations.

/// Run `kernel` in the AVX2 build where the CPU has AVX2 (detected once, then cached by std).
/// The kernel must be an `#[inline(always)]` closure, so that its body is compiled into the
/// AVX2 instance.
#[inline(always)]
pub(crate) fn dispatch<R>(kernel: impl FnOnce() -> R) -> R {
    dispatch_wide(
        #[inline(always)]
        |_| kernel(),
    )
}

/// `kernel`, compiled for AVX2.
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2")]
pub(crate) unsafe fn with_avx2<R>(kernel: impl FnOnce() -> R) -> R {
    kernel()
}

/// `dispatch` for a kernel with a path of its own for AVX2: it is told whether it runs in the
/// AVX2 build (`true` only where the CPU has AVX2, so that it may call AVX2 intrinsics).
#[inline(always)]
pub(crate) fn dispatch_wide<R>(kernel: impl FnOnce(bool) -> R) -> R {
    #[cfg(target_arch = "x86_64")]
    if std::arch::is_x86_feature_detected!("avx2") {
        // SAFETY: the CPU has AVX2, checked just above.
        return unsafe {
            with_avx2(
                #[inline(always)]
                || kernel(true),
            )
        };
    }
    kernel(false)
}
