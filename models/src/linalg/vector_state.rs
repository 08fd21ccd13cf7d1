//! A clean vector-register state before this crate's own loops.
//!
//! faer's dense kernels choose AVX or AVX-512 at run time; the rest of this crate is compiled
//! for baseline x86-64 (SSE2, so that the FMUs load on any x86-64 host). Wide instructions that
//! leave the upper halves of the vector registers dirty make every later SSE instruction pay
//! for it until a `vzeroupper`. Measured on the project's machine: 1,000 full-order abdomen
//! steps took 505 ms after one modal set-up in the same process (Lanczos and the Galerkin
//! products run in faer) and 155 ms without it, or with a `vzeroupper` in between — the
//! "one benchmark three times slower, a different one each run" seen before in BENCHMARKS.md.
//! [`clear`] executes it: at each integrator step, and after faer's factorization and
//! supernodal solve.

/// Executes `vzeroupper` where the CPU has AVX; nothing elsewhere. Costs a few cycles.
pub fn clear() {
    #[cfg(target_arch = "x86_64")]
    if std::arch::is_x86_feature_detected!("avx") {
        // SAFETY: the CPU supports AVX (checked just above), all `vzeroupper` needs.
        #[allow(unsafe_code)]
        unsafe {
            zero_upper()
        }
    }
}

#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx")]
fn zero_upper() {
    std::arch::x86_64::_mm256_zeroupper();
}
