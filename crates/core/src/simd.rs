//! Run-time choice of the SIMD kernels. The binary is built for the baseline x86-64 target
//! (SSE2); the kernels that gain from wider registers (the BVH's eight-box slab test, the
//! Sobol sampler's integer lanes, the eight-lane Lambertian bounce in
//! [`crate::lanes_avx::F8Avx`]) also exist compiled for AVX2 and for AVX-512 (the same
//! eight-lane code, which AVX-512VL encodes with 32 registers and mask registers;
//! [`crate::level_fns!`]) and are picked once per process from what the CPU reports
//! (`is_x86_feature_detected!`), the way Embree and Mitsuba's Dr.Jit pick theirs. Every kernel performs the same IEEE operations in the same
//! order at every level (no fused multiply-adds), so images are bit-identical whichever
//! level runs (`tests/determinism.rs` forces each one).
//!
//! Without a choice the kernels run at [`Level::preferred`]: AVX2 where the CPU has it,
//! even beside AVX-512, whose build of the same kernels measured slower on the whole suite
//! (see there). `PENUMBRA_SIMD=sse2|avx2|avx512` chooses the level (for testing, to compare
//! kernels, or to take AVX-512 where it pays).

use std::fmt;
use std::sync::atomic::{AtomicU8, Ordering};

/// A set of kernels, from the narrowest to the widest.
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord)]
pub enum Level {
    /// The baseline: SSE2 on x86-64, plain code elsewhere.
    Sse2 = 1,
    /// AVX2 (eight `f32` or `i32` lanes per instruction).
    Avx2 = 2,
    /// AVX-512 F, VL, BW and DQ: the AVX2 kernels compiled with the wider instruction set.
    Avx512 = 3,
}

/// Compiles one function body twice, as `unsafe fn [avx2_name, avx512_name] ...`: once with
/// AVX2's target features and once with [`Level::Avx512`]'s (listed here once: an attribute
/// takes only a literal). The body usually calls an `#[inline(always)]` kernel, which is
/// then compiled whole at each level.
#[macro_export]
macro_rules! level_fns {
    ($(#[$meta:meta])* $vis:vis unsafe fn [$avx2:ident, $avx512:ident] $($rest:tt)*) => {
        $(#[$meta])*
        #[target_feature(enable = "avx2")]
        $vis unsafe fn $avx2 $($rest)*

        $(#[$meta])*
        #[target_feature(enable = "avx512f,avx512vl,avx512bw,avx512dq")]
        $vis unsafe fn $avx512 $($rest)*
    };
}

/// Runs the kernel of the CPU's level ([`level`]): the AVX-512 expression, the AVX2 one
/// (each calling a [`level_fns!`] function, in an `unsafe` block the macro provides), or
/// the portable one. Safety: a level is chosen only where the CPU runs it.
#[macro_export]
macro_rules! at_level {
    (avx512: $avx512:expr, avx2: $avx2:expr, portable: $portable:expr $(,)?) => {{
        #[cfg(target_arch = "x86_64")]
        let result = match $crate::simd::level() {
            // SAFETY: the CPU runs the level's instructions (checked when it was chosen).
            $crate::simd::Level::Avx512 => unsafe { $avx512 },
            // SAFETY: as above.
            $crate::simd::Level::Avx2 => unsafe { $avx2 },
            $crate::simd::Level::Sse2 => $portable,
        };
        #[cfg(not(target_arch = "x86_64"))]
        let result = $portable;
        result
    }};
}

impl Level {
    /// Every level, narrowest first.
    pub const ALL: [Level; 3] = [Level::Sse2, Level::Avx2, Level::Avx512];

    /// The name `PENUMBRA_SIMD` takes and reports print.
    pub fn name(self) -> &'static str {
        match self {
            Level::Sse2 => "sse2",
            Level::Avx2 => "avx2",
            Level::Avx512 => "avx512",
        }
    }

    /// Whether this CPU runs the level's kernels.
    pub fn supported(self) -> bool {
        match self {
            Level::Sse2 => true,
            #[cfg(target_arch = "x86_64")]
            Level::Avx2 => is_x86_feature_detected!("avx2"),
            #[cfg(target_arch = "x86_64")]
            Level::Avx512 => {
                is_x86_feature_detected!("avx512f")
                    && is_x86_feature_detected!("avx512vl")
                    && is_x86_feature_detected!("avx512bw")
                    && is_x86_feature_detected!("avx512dq")
            }
            #[cfg(not(target_arch = "x86_64"))]
            Level::Avx2 | Level::Avx512 => false,
        }
    }

    /// The widest level this CPU runs.
    pub fn best() -> Level {
        *Level::ALL.iter().rev().find(|l| l.supported()).unwrap_or(&Level::Sse2)
    }

    /// The level used unless `PENUMBRA_SIMD` names another: AVX2 where the CPU runs it,
    /// else the baseline. Not AVX-512: on an Intel Xeon with AVX-512 F/VL/BW/DQ (2 vCPUs,
    /// December 2026) its build of the same eight-lane kernels made the whole suite slower
    /// (`run.sh suite`, two alternating runs each, samples/s against Mitsuba: cbox 0.93x
    /// against 0.99x with AVX2, Bitterli's box 0.79x against 0.85x, env-materials 1.08x
    /// against 1.10x), as Intel cores slow their vector units once 512-bit instructions
    /// run; an earlier AVX-512 machine had it 1-2% ahead. Images are the same bits at
    /// every level, so the choice changes only the speed.
    pub fn preferred() -> Level {
        if Level::Avx2.supported() {
            Level::Avx2
        } else {
            Level::Sse2
        }
    }

    /// The level named `name` (case-insensitive), if it is one.
    pub fn parse(name: &str) -> Option<Level> {
        Level::ALL
            .into_iter()
            .find(|l| l.name().eq_ignore_ascii_case(name.trim()))
    }
}

impl fmt::Display for Level {
    fn fmt(&self, f: &mut fmt::Formatter) -> fmt::Result {
        f.write_str(self.name())
    }
}

/// The level in use; 0 until first asked for.
static LEVEL: AtomicU8 = AtomicU8::new(0);

/// The level the kernels run at: [`Level::preferred`], or the one `PENUMBRA_SIMD` names (a
/// level the CPU lacks, or a name that is none, falls back to the preferred one with a note
/// on standard error), or what [`set_level`] chose.
#[inline(always)]
pub fn level() -> Level {
    match LEVEL.load(Ordering::Relaxed) {
        1 => Level::Sse2,
        2 => Level::Avx2,
        3 => Level::Avx512,
        _ => detect(),
    }
}

#[cold]
fn detect() -> Level {
    let preferred = Level::preferred();
    let chosen = match std::env::var("PENUMBRA_SIMD") {
        Ok(name) => match Level::parse(&name) {
            Some(l) if l.supported() => l,
            Some(l) => {
                eprintln!("note: PENUMBRA_SIMD={name}: this CPU lacks {l}; using {preferred}");
                preferred
            }
            None => {
                let names: Vec<_> = Level::ALL.iter().map(|l| l.name()).collect();
                eprintln!(
                    "note: PENUMBRA_SIMD={name} is not one of {}; using {preferred}",
                    names.join(", ")
                );
                preferred
            }
        },
        Err(_) => preferred,
    };
    LEVEL.store(chosen as u8, Ordering::Relaxed);
    chosen
}

/// Makes the kernels run at `level` from now on; an error if this CPU lacks it.
pub fn set_level(level: Level) -> Result<(), String> {
    if !level.supported() {
        return Err(format!("this CPU does not run {level} kernels"));
    }
    LEVEL.store(level as u8, Ordering::Relaxed);
    Ok(())
}

/// Asks the caches for the lines holding `value`: a hint that lets the loads of several
/// independent lookups (eight lanes' table entries, the children of a tree node) wait on
/// memory together instead of one after another. Does nothing where the target has no
/// prefetch instruction.
#[inline(always)]
pub fn prefetch<T>(value: &T) {
    #[cfg(target_arch = "x86_64")]
    {
        use std::arch::x86_64::{_mm_prefetch, _MM_HINT_T0};
        let p = value as *const T as *const i8;
        let size = std::mem::size_of::<T>().max(1);
        // Every 64 bytes from the start, and the last byte unless the value fills whole
        // lines: each line the value touches.
        let whole_lines = size.is_multiple_of(64) && std::mem::align_of::<T>().is_multiple_of(64);
        let last = (!whole_lines).then_some(size - 1);
        for offset in (0..size).step_by(64).chain(last) {
            // SAFETY: a prefetch is only a hint, and the address lies inside `value`.
            unsafe { _mm_prefetch(p.add(offset), _MM_HINT_T0) };
        }
    }
    #[cfg(not(target_arch = "x86_64"))]
    let _ = value;
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn names_round_trip_and_baseline_is_always_there() {
        for l in Level::ALL {
            assert_eq!(Level::parse(l.name()), Some(l));
            assert_eq!(Level::parse(&l.name().to_uppercase()), Some(l));
        }
        assert_eq!(Level::parse("avx9"), None);
        assert!(Level::Sse2.supported());
        assert!(Level::best().supported());
        assert!(Level::preferred().supported() && Level::preferred() <= Level::best());
        assert!(level().supported());
    }
}
