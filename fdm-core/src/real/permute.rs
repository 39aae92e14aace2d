//! An instruction set's lane permutes, for table look-ups in lanes: a lane
//! step that reads each lane's entry of a small constant table can fetch it
//! with one in-register permute where the instruction set has one, instead
//! of a select per entry. The fleet kernel ([`super::kernel`]) hands its
//! instruction set's [`Permutes`] to [`super::LaneModel::step_lanes_permuting`]:
//! pulp's AVX-512 token (`vpermt2ps`) in the x86-64-v4 copy, [`NoPermutes`]
//! in every other (and in the scalar step), where the caller keeps its
//! portable form. A permute moves bits: the entries fetched are the table's,
//! whichever form fetched them.

/// Lane permutes of an instruction set, for table look-ups in lanes: pulp's
/// AVX-512 token (`vpermt2ps`) in the fleet kernel's x86-64-v4 copy,
/// [`NoPermutes`] elsewhere (the caller's portable form). A permute moves
/// bits: the entries fetched are the table's, whichever form fetched them.
pub trait Permutes: Copy + core::fmt::Debug + Send + Sync + 'static {
    /// Lane `l` of the result is `table[index[l] % 32]`, for every lane, if
    /// this instruction set permutes `N` lanes out of 32 entries in
    /// registers; `None` otherwise (the caller's portable form). Constant for
    /// a given `Self` and `N`, so the branch on it is folded.
    fn permute_32<const N: usize>(self, table: &[f32; 32], index: [u32; N]) -> Option<[f32; N]>;
}

/// No permutes: look-ups keep their portable form.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct NoPermutes;

impl Permutes for NoPermutes {
    #[inline(always)]
    fn permute_32<const N: usize>(self, _: &[f32; 32], _: [u32; N]) -> Option<[f32; N]> {
        None
    }
}

/// AVX-512: 16 lanes out of two registers by `vpermt2ps`
/// (`_mm512_permutex2var_ps`, which reads the low five bits of each index).
/// The token exists only on a CPU that has AVX-512, and its wrapper is the
/// intrinsic, inlined into the kernel's AVX-512 copy.
#[cfg(all(feature = "std", target_arch = "x86_64"))]
impl Permutes for pulp::x86::V4 {
    #[inline(always)]
    fn permute_32<const N: usize>(self, table: &[f32; 32], index: [u32; N]) -> Option<[f32; N]> {
        use core::arch::x86_64::{__m512, __m512i};
        if N != 16 {
            return None;
        }
        let lo: [f32; 16] = core::array::from_fn(|l| table[l]);
        let hi: [f32; 16] = core::array::from_fn(|l| table[16 + l]);
        let index: [u32; 16] = core::array::from_fn(|l| index[l]);
        let out: __m512 = self.avx512f._mm512_permutex2var_ps(
            pulp::cast::<[f32; 16], __m512>(lo),
            pulp::cast::<[u32; 16], __m512i>(index),
            pulp::cast::<[f32; 16], __m512>(hi),
        );
        let out: [f32; 16] = pulp::cast(out);
        Some(core::array::from_fn(|l| out[l]))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn no_permutes_are_none() {
        assert_eq!(NoPermutes.permute_32(&[1.0; 32], [3_u32; 16]), None);
    }

    /// Every index of every lane fetches its entry (the low five bits), bit
    /// for bit, NaN payloads and signed zeros included.
    #[cfg(all(feature = "std", target_arch = "x86_64"))]
    #[test]
    fn avx512_permutes_fetch_each_lanes_entry() {
        let Some(simd) = pulp::x86::V4::try_new() else {
            return;
        };
        let table: [f32; 32] = core::array::from_fn(|k| match k {
            3 => -0.0,
            7 => f32::from_bits(0x7fc0_1234),
            _ => k as f32 * 1.5 - 7.0,
        });
        for shift in 0..64_u32 {
            let index: [u32; 16] = core::array::from_fn(|l| (l as u32 * 7 + shift) % 64);
            let out = simd.permute_32(&table, index).unwrap();
            for l in 0..16 {
                assert_eq!(out[l].to_bits(), table[(index[l] % 32) as usize].to_bits());
            }
        }
        assert_eq!(simd.permute_32(&table, [0_u32; 8]), None);
    }
}
