//! ARMv7E-M DSP-extension SIMD on two `i16` packed in a `u32` (low half = real part).
//!
//! On the Cortex-M7 each function is one instruction (stable inline `asm!`); elsewhere it is the
//! same arithmetic written out in Rust, bit for bit (the firmware self-test checks this on QEMU).
//! The names are the instructions'. Lanes of the non-saturating ops wrap; callers prove they
//! cannot overflow.

// The DSP extension's instructions are inline `asm!` (each wrapper says why it is sound).
#![allow(unsafe_code)]

#[cfg(arm_dsp)]
mod imp {
    use core::arch::asm;

    macro_rules! binary {
        ($($(#[$m:meta])* $name:ident = $ins:literal;)*) => {$(
            $(#[$m])*
            #[inline(always)]
            pub fn $name(a: u32, b: u32) -> u32 {
                let r: u32;
                // SAFETY: a register-only DSP instruction; it may set the GE flags, nothing else.
                unsafe { asm!(concat!($ins, " {r}, {a}, {b}"), r = lateout(reg) r, a = in(reg) a, b = in(reg) b, options(pure, nomem, nostack)) };
                r
            }
        )*};
    }

    // One pair step of the unrolled block loops, written out line by line (not `.rept`), so
    // that LLVM, which sizes inline assembly by its lines, places constant pools in reach.
    macro_rules! widen_step {
        () => {
            concat!(
                "ldrd {w0}, {w1}, [{xp}], #8\n",
                "ldm {ap}, {{r0, r1, r2, r3}}\n",
                "sxtah r0, r0, {w0}\n",
                "add r1, r1, {w0}, asr #16\n",
                "sxtah r2, r2, {w1}\n",
                "add r3, r3, {w1}, asr #16\n",
                "stm {ap}!, {{r0, r1, r2, r3}}",
            )
        };
    }
    macro_rules! mac_step {
        () => {
            concat!(
                "ldrd {w0}, {w1}, [{xp}], #8\n",
                "ldm {ap}, {{r0, r1, r2, r3}}\n",
                "smlsd r0, {c}, {w0}, r0\n",
                "smladx r1, {c}, {w0}, r1\n",
                "smlsd r2, {c}, {w1}, r2\n",
                "smladx r3, {c}, {w1}, r3\n",
                "stm {ap}!, {{r0, r1, r2, r3}}",
            )
        };
    }

    binary! {
        sadd16 = "sadd16";
        ssub16 = "ssub16";
        shadd16 = "shadd16";
        shsub16 = "shsub16";
        sasx = "sasx";
        ssax = "ssax";
        shasx = "shasx";
        shsax = "shsax";
        smuad = "smuad";
    }

    /// Low half of `a`, high half of `b << 1`.
    #[inline(always)]
    pub fn pkhbt_lsl1(a: u32, b: u32) -> u32 {
        let r: u32;
        // SAFETY: a register-only instruction without side effects.
        unsafe {
            asm!("pkhbt {r}, {a}, {b}, lsl #1", r = lateout(reg) r, a = in(reg) a, b = in(reg) b, options(pure, nomem, nostack, preserves_flags))
        };
        r
    }

    macro_rules! mac {
        ($($name:ident = $ins:literal;)*) => {$(
            #[inline(always)]
            pub fn $name(a: u32, b: u32, acc: i32) -> i32 {
                let r: i32;
                // SAFETY: a register-only DSP instruction; it may set the sticky Q flag, nothing else.
                unsafe { asm!(concat!($ins, " {r}, {a}, {b}, {c}"), r = lateout(reg) r, a = in(reg) a, b = in(reg) b, c = in(reg) acc, options(pure, nomem, nostack)) };
                r
            }
        )*};
    }

    mac! {
        smlsd = "smlsd";
        smladx = "smladx";
    }

    macro_rules! mac_long {
        ($($name:ident = $ins:literal;)*) => {$(
            #[inline(always)]
            pub fn $name(a: u32, b: u32, acc: i64) -> i64 {
                let (mut lo, mut hi) = (acc as u32, (acc >> 32) as u32);
                // SAFETY: a register-only DSP instruction without side effects.
                unsafe { asm!(concat!($ins, " {lo}, {hi}, {a}, {b}"), lo = inout(reg) lo, hi = inout(reg) hi, a = in(reg) a, b = in(reg) b, options(pure, nomem, nostack, preserves_flags)) };
                (((hi as u64) << 32) | lo as u64) as i64
            }
        )*};
    }

    mac_long! {
        smlsld = "smlsld";
        smlaldx = "smlaldx";
    }

    /// One pair of elements: two `LDRD`s (post-incremented) and four dual MACs.
    macro_rules! mac_pair {
        () => {
            "ldrd {x0}, {x1}, [{xp}], #8\n\
             ldrd {w0}, {w1}, [{wp}], #8\n\
             smlsld {rl}, {rh}, {x0}, {w0}\n\
             smlaldx {il}, {ih}, {x0}, {w0}\n\
             smlsld {rl}, {rh}, {x1}, {w1}\n\
             smlaldx {il}, {ih}, {x1}, {w1}"
        };
    }

    /// `Σ (smlsld, smlaldx)` over the first `2·pairs` words of `x` and `w` (callers check the
    /// lengths): two `LDRD`s and four MACs per pair. The main loop takes four pairs per turn
    /// (3.5 instructions per element); a one-pair loop takes the rest.
    ///
    /// # Safety
    /// `x` and `w` must each hold at least `2·pairs` words and `pairs > 0`.
    #[inline(always)]
    pub unsafe fn mac_pairs(x: &[u32], w: &[u32], pairs: usize, re: i64, im: i64) -> (i64, i64) {
        let (mut rl, mut rh, mut il, mut ih) =
            (re as u32, (re >> 32) as u32, im as u32, (im >> 32) as u32);
        let (mut xp, mut wp) = (x.as_ptr(), w.as_ptr());
        let (quads, rest) = (pairs / 4, pairs % 4);
        if quads > 0 {
            // SAFETY: `4·quads ≤ pairs` pairs are readable behind both pointers; the loop reads
            // exactly those, advances the pointers past them and touches no other memory.
            unsafe {
                asm!(
                    "2:",
                    mac_pair!(),
                    mac_pair!(),
                    mac_pair!(),
                    mac_pair!(),
                    "subs {n}, {n}, #1",
                    "bne 2b",
                    xp = inout(reg) xp,
                    wp = inout(reg) wp,
                    n = inout(reg) quads => _,
                    x0 = out(reg) _, x1 = out(reg) _, w0 = out(reg) _, w1 = out(reg) _,
                    rl = inout(reg) rl, rh = inout(reg) rh, il = inout(reg) il, ih = inout(reg) ih,
                    options(readonly, nostack),
                );
            }
        }
        if rest > 0 {
            // SAFETY: the `rest` pairs after the quads are readable behind both pointers.
            unsafe {
                asm!(
                    "2:",
                    mac_pair!(),
                    "subs {n}, {n}, #1",
                    "bne 2b",
                    xp = inout(reg) xp => _,
                    wp = inout(reg) wp => _,
                    n = inout(reg) rest => _,
                    x0 = out(reg) _, x1 = out(reg) _, w0 = out(reg) _, w1 = out(reg) _,
                    rl = inout(reg) rl, rh = inout(reg) rh, il = inout(reg) il, ih = inout(reg) ih,
                    options(readonly, nostack),
                );
            }
        }
        (
            (((rh as u64) << 32) | rl as u64) as i64,
            (((ih as u64) << 32) | il as u64) as i64,
        )
    }

    /// `acc[2i] += re(x[i])`, `acc[2i + 1] += im(x[i])` (wrapping) for the first `4·quads` words
    /// of `x`: per pair of words one `LDRD` of samples, one `LDM` and one `STM` of the four sums
    /// (r0–r3), two `SXTAH` and two `ADD …, ASR #16`; two pairs per turn (four instructions per
    /// word with the loop).
    ///
    /// # Safety
    /// `x` must hold at least `4·quads` words, `acc` at least `8·quads`, and `quads > 0`.
    #[inline(always)]
    pub unsafe fn widen_add_quads(acc: &mut [u32], x: &[u32], quads: usize) {
        // SAFETY: the loop reads `4·quads` words of `x` and reads and writes `8·quads` words of
        // `acc`, which the caller guarantees, and touches no other memory.
        unsafe {
            asm!(
                "2:",
                "ldrd {w0}, {w1}, [{xp}], #8",
                "ldm {ap}, {{r0, r1, r2, r3}}",
                "sxtah r0, r0, {w0}",
                "add r1, r1, {w0}, asr #16",
                "sxtah r2, r2, {w1}",
                "add r3, r3, {w1}, asr #16",
                "stm {ap}!, {{r0, r1, r2, r3}}",
                "ldrd {w0}, {w1}, [{xp}], #8",
                "ldm {ap}, {{r0, r1, r2, r3}}",
                "sxtah r0, r0, {w0}",
                "add r1, r1, {w0}, asr #16",
                "sxtah r2, r2, {w1}",
                "add r3, r3, {w1}, asr #16",
                "stm {ap}!, {{r0, r1, r2, r3}}",
                "subs {n}, {n}, #1",
                "bne 2b",
                xp = inout(reg) x.as_ptr() => _,
                ap = inout(reg) acc.as_mut_ptr() => _,
                n = inout(reg) quads => _,
                w0 = out(reg) _, w1 = out(reg) _,
                out("r0") _, out("r1") _, out("r2") _, out("r3") _,
                options(nostack),
            );
        }
    }

    /// [`widen_add_quads`] over `blocks` blocks of 16 words, eight pair steps unrolled per
    /// block (3.6 instructions per word with the loop).
    ///
    /// # Safety
    /// `x` must hold at least `16·blocks` words, `acc` at least `32·blocks`, and `blocks > 0`.
    #[inline(always)]
    pub unsafe fn widen_add_blocks16(acc: &mut [u32], x: &[u32], blocks: usize) {
        // SAFETY: the loop reads `16·blocks` words of `x` and reads and writes `32·blocks`
        // words of `acc`, which the caller guarantees, and touches no other memory.
        unsafe {
            asm!(
                "2:",
                widen_step!(), widen_step!(), widen_step!(), widen_step!(),
                widen_step!(), widen_step!(), widen_step!(), widen_step!(),
                "subs {n}, {n}, #1",
                "bne.w 2b",
                xp = inout(reg) x.as_ptr() => _,
                ap = inout(reg) acc.as_mut_ptr() => _,
                n = inout(reg) blocks => _,
                w0 = out(reg) _, w1 = out(reg) _,
                out("r0") _, out("r1") _, out("r2") _, out("r3") _,
                options(nostack),
            );
        }
    }

    /// `acc[2i] += re(c·x[i])`, `acc[2i + 1] += im(c·x[i])` (wrapping `i32`, the products exact)
    /// for the first `4·quads` words of `x`, `c` one packed Q15 coefficient: per pair of words
    /// one `LDRD`, an `LDM` and an `STM` of the sums, two `SMLSD` and two `SMLADX`; two pairs a
    /// turn (four instructions per word with the loop, as [`widen_add_quads`]).
    ///
    /// # Safety
    /// As [`widen_add_quads`].
    #[inline(always)]
    pub unsafe fn mac_add_quads(acc: &mut [u32], x: &[u32], c: u32, quads: usize) {
        // SAFETY: as `widen_add_quads`: `4·quads` words of `x` read, `8·quads` of `acc` read
        // and written, nothing else touched.
        unsafe {
            asm!(
                "2:",
                "ldrd {w0}, {w1}, [{xp}], #8",
                "ldm {ap}, {{r0, r1, r2, r3}}",
                "smlsd r0, {c}, {w0}, r0",
                "smladx r1, {c}, {w0}, r1",
                "smlsd r2, {c}, {w1}, r2",
                "smladx r3, {c}, {w1}, r3",
                "stm {ap}!, {{r0, r1, r2, r3}}",
                "ldrd {w0}, {w1}, [{xp}], #8",
                "ldm {ap}, {{r0, r1, r2, r3}}",
                "smlsd r0, {c}, {w0}, r0",
                "smladx r1, {c}, {w0}, r1",
                "smlsd r2, {c}, {w1}, r2",
                "smladx r3, {c}, {w1}, r3",
                "stm {ap}!, {{r0, r1, r2, r3}}",
                "subs {n}, {n}, #1",
                "bne 2b",
                xp = inout(reg) x.as_ptr() => _,
                ap = inout(reg) acc.as_mut_ptr() => _,
                n = inout(reg) quads => _,
                c = in(reg) c,
                w0 = out(reg) _, w1 = out(reg) _,
                out("r0") _, out("r1") _, out("r2") _, out("r3") _,
                options(nostack),
            );
        }
    }
    /// For each of `blocks` blocks of 16 words of `x`: `acc += c_b · x` per word (as
    /// [`mac_add_quads`]), `c_b` the block's word of `coefficients`. Per block one `LDR` of the
    /// coefficient, eight pair steps unrolled (`LDRD`, `LDM`, two `SMLSD`, two `SMLADX`, `STM`)
    /// and the loop: 3.7 instructions per word.
    ///
    /// # Safety
    /// `x` must hold at least `16·blocks` words, `acc` at least `32·blocks`, `coefficients` at
    /// least `blocks`, and `blocks > 0`.
    #[inline(always)]
    pub unsafe fn mac_add_blocks16(
        acc: &mut [u32],
        x: &[u32],
        coefficients: &[u32],
        blocks: usize,
    ) {
        // SAFETY: the loop reads `16·blocks` words of `x` and `blocks` of `coefficients`, and
        // reads and writes `32·blocks` words of `acc`, which the caller guarantees.
        unsafe {
            asm!(
                "3:",
                "ldr {c}, [{cp}], #4",
                mac_step!(), mac_step!(), mac_step!(), mac_step!(),
                mac_step!(), mac_step!(), mac_step!(), mac_step!(),
                "subs {nb}, {nb}, #1",
                "bne.w 3b",
                xp = inout(reg) x.as_ptr() => _,
                ap = inout(reg) acc.as_mut_ptr() => _,
                cp = inout(reg) coefficients.as_ptr() => _,
                nb = inout(reg) blocks => _,
                c = out(reg) _,
                w0 = out(reg) _, w1 = out(reg) _,
                out("r0") _, out("r1") _, out("r2") _, out("r3") _,
                options(nostack),
            );
        }
    }
}

#[cfg(not(arm_dsp))]
mod imp {
    #[inline(always)]
    fn lo(x: u32) -> i32 {
        x as u16 as i16 as i32
    }
    #[inline(always)]
    fn hi(x: u32) -> i32 {
        (x >> 16) as u16 as i16 as i32
    }
    #[inline(always)]
    fn pack(lo: i32, hi: i32) -> u32 {
        (lo as u16 as u32) | ((hi as u16 as u32) << 16)
    }
    pub fn sadd16(a: u32, b: u32) -> u32 {
        pack(lo(a) + lo(b), hi(a) + hi(b))
    }
    pub fn ssub16(a: u32, b: u32) -> u32 {
        pack(lo(a) - lo(b), hi(a) - hi(b))
    }
    pub fn shadd16(a: u32, b: u32) -> u32 {
        pack((lo(a) + lo(b)) >> 1, (hi(a) + hi(b)) >> 1)
    }
    pub fn shsub16(a: u32, b: u32) -> u32 {
        pack((lo(a) - lo(b)) >> 1, (hi(a) - hi(b)) >> 1)
    }
    pub fn sasx(a: u32, b: u32) -> u32 {
        pack(lo(a) - hi(b), hi(a) + lo(b))
    }
    pub fn ssax(a: u32, b: u32) -> u32 {
        pack(lo(a) + hi(b), hi(a) - lo(b))
    }
    pub fn shasx(a: u32, b: u32) -> u32 {
        pack((lo(a) - hi(b)) >> 1, (hi(a) + lo(b)) >> 1)
    }
    pub fn shsax(a: u32, b: u32) -> u32 {
        pack((lo(a) + hi(b)) >> 1, (hi(a) - lo(b)) >> 1)
    }
    pub fn pkhbt_lsl1(a: u32, b: u32) -> u32 {
        (a & 0xFFFF) | ((b << 1) & 0xFFFF_0000)
    }
    pub fn smuad(a: u32, b: u32) -> u32 {
        (lo(a) * lo(b)).wrapping_add(hi(a) * hi(b)) as u32
    }
    pub fn smlsd(a: u32, b: u32, acc: i32) -> i32 {
        (lo(a) * lo(b))
            .wrapping_sub(hi(a) * hi(b))
            .wrapping_add(acc)
    }
    pub fn smladx(a: u32, b: u32, acc: i32) -> i32 {
        (lo(a) * hi(b))
            .wrapping_add(hi(a) * lo(b))
            .wrapping_add(acc)
    }
    pub fn smlsld(a: u32, b: u32, acc: i64) -> i64 {
        acc.wrapping_add(lo(a) as i64 * lo(b) as i64 - hi(a) as i64 * hi(b) as i64)
    }
    pub fn smlaldx(a: u32, b: u32, acc: i64) -> i64 {
        acc.wrapping_add(lo(a) as i64 * hi(b) as i64 + hi(a) as i64 * lo(b) as i64)
    }
    /// See the M7 version.
    ///
    /// # Safety
    /// None needed here (slices are indexed safely); the signature matches the M7's.
    pub unsafe fn mac_pairs(x: &[u32], w: &[u32], pairs: usize, re: i64, im: i64) -> (i64, i64) {
        let (mut re, mut im) = (re, im);
        for (&a, &b) in x.iter().zip(w).take(2 * pairs) {
            re = smlsld(a, b, re);
            im = smlaldx(a, b, im);
        }
        (re, im)
    }
    /// See the M7 version.
    ///
    /// # Safety
    /// None needed here; the signature matches the M7's.
    pub unsafe fn widen_add_quads(acc: &mut [u32], x: &[u32], quads: usize) {
        for (a, &w) in acc.chunks_exact_mut(2).zip(x).take(4 * quads) {
            a[0] = a[0].wrapping_add(lo(w) as u32);
            a[1] = a[1].wrapping_add(hi(w) as u32);
        }
    }
    /// See the M7 version.
    ///
    /// # Safety
    /// None needed here; the signature matches the M7's.
    pub unsafe fn widen_add_blocks16(acc: &mut [u32], x: &[u32], blocks: usize) {
        // SAFETY: none needed (see above).
        unsafe { widen_add_quads(acc, x, 4 * blocks) };
    }
    /// See the M7 version.
    ///
    /// # Safety
    /// None needed here; the signature matches the M7's.
    pub unsafe fn mac_add_quads(acc: &mut [u32], x: &[u32], c: u32, quads: usize) {
        for (a, &w) in acc.chunks_exact_mut(2).zip(x).take(4 * quads) {
            a[0] = smlsd(c, w, a[0] as i32) as u32;
            a[1] = smladx(c, w, a[1] as i32) as u32;
        }
    }
    /// See the M7 version.
    ///
    /// # Safety
    /// None needed here; the signature matches the M7's.
    pub unsafe fn mac_add_blocks16(
        acc: &mut [u32],
        x: &[u32],
        coefficients: &[u32],
        blocks: usize,
    ) {
        for ((a, x), &c) in acc
            .chunks_exact_mut(32)
            .zip(x.chunks_exact(16))
            .zip(coefficients)
            .take(blocks)
        {
            // SAFETY: none needed (see above).
            unsafe { mac_add_quads(a, x, c, 4) };
        }
    }
}

/// `Σₑ xₑ·wₑ` of packed Q15 complex words, exact in `i64`: the real part by `SMLSLD`, the
/// imaginary by `SMLALDX`, over the shorter of the two slices. O(len); on the M7 3.5
/// instructions per element (a hand-scheduled loop over `LDRD` pairs, four pairs per turn).
#[inline]
pub fn complex_mac(x: &[u32], w: &[u32]) -> (i64, i64) {
    let len = x.len().min(w.len());
    let pairs = len / 2;
    let (mut re, mut im) = if pairs > 0 {
        // SAFETY: both slices hold at least `2·pairs` words and `pairs > 0`.
        unsafe { mac_pairs(x, w, pairs, 0, 0) }
    } else {
        (0, 0)
    };
    if let (Some(&a), Some(&b), true) = (
        x.get(len.wrapping_sub(1)),
        w.get(len.wrapping_sub(1)),
        len % 2 == 1,
    ) {
        re = smlsld(a, b, re);
        im = smlaldx(a, b, im);
    }
    (re, im)
}

/// Adds packed Q15 complex words into `i32` sums, wrapping: `acc[2i] += re(x[i])` and
/// `acc[2i + 1] += im(x[i])`, over the words `acc` has room for. O(len); on the M7 3.6
/// instructions per word (hand-scheduled loops, `LDM`/`STM` of the sums, with `SXTAH`: blocks
/// of 16 words, then of 4, then single words).
#[inline]
pub fn widen_add(acc: &mut [u32], x: &[u32]) {
    let len = x.len().min(acc.len() / 2);
    let blocks = len / 16;
    if blocks > 0 {
        // SAFETY: `x` holds `len ≥ 16·blocks` words, `acc` at least `2·len ≥ 32·blocks`.
        unsafe { widen_add_blocks16(acc, x, blocks) };
    }
    let (acc, x, len) = (
        acc.get_mut(32 * blocks..).unwrap_or_default(),
        x.get(16 * blocks..).unwrap_or_default(),
        len - 16 * blocks,
    );
    let quads = len / 4;
    if quads > 0 {
        // SAFETY: `x` holds `len ≥ 4·quads` words, `acc` at least `2·len ≥ 8·quads`.
        unsafe { widen_add_quads(acc, x, quads) };
    }
    let (acc, x) = (
        acc.get_mut(8 * quads..2 * len).unwrap_or_default(),
        x.get(4 * quads..len).unwrap_or_default(),
    );
    for (a, &w) in acc.chunks_exact_mut(2).zip(x) {
        a[0] = a[0].wrapping_add(w as i16 as u32);
        a[1] = a[1].wrapping_add(((w as i32) >> 16) as u32);
    }
}

/// [`mac_add`] with one coefficient per block of 16 words: `acc[2i..2i + 2] += c[i / 16] ·
/// x[i]`, over the words `acc` and `coefficients` have room for (a last block may be short).
/// O(len); on the M7 3.7 instructions per word (the blocks' loop in assembly, unrolled).
#[inline]
pub fn mac_add_blocks(acc: &mut [u32], x: &[u32], coefficients: &[u32]) {
    let len = x.len().min(acc.len() / 2).min(16 * coefficients.len());
    let full = len / 16;
    if full > 0 {
        // SAFETY: `x` holds `len ≥ 16·full` words, `acc` at least `2·len ≥ 32·full`, and
        // `coefficients` at least `full`.
        unsafe { mac_add_blocks16(acc, x, coefficients, full) };
    }
    if let (Some(acc), Some(x), Some(&c)) = (
        acc.get_mut(32 * full..2 * len),
        x.get(16 * full..len),
        coefficients.get(full),
    ) {
        mac_add(acc, x, c);
    }
}

/// Adds the products of packed Q15 complex words with one packed coefficient `c` into `i32`
/// sums, wrapping: `acc[2i] += re(c·x[i])`, `acc[2i + 1] += im(c·x[i])`, each product exact
/// (`SMLSD` and `SMLADX`), over the words `acc` has room for. The sums are exact while the
/// true ones fit in `i32`. O(len); on the M7 four instructions per word, as [`widen_add`].
#[inline]
pub fn mac_add(acc: &mut [u32], x: &[u32], c: u32) {
    let len = x.len().min(acc.len() / 2);
    let quads = len / 4;
    if quads > 0 {
        // SAFETY: `x` holds `len ≥ 4·quads` words, `acc` at least `2·len ≥ 8·quads`.
        unsafe { mac_add_quads(acc, x, c, quads) };
    }
    let (acc, x) = (
        acc.get_mut(8 * quads..2 * len).unwrap_or_default(),
        x.get(4 * quads..len).unwrap_or_default(),
    );
    for (a, &w) in acc.chunks_exact_mut(2).zip(x) {
        a[0] = smlsd(c, w, a[0] as i32) as u32;
        a[1] = smladx(c, w, a[1] as i32) as u32;
    }
}

pub use imp::*;

/// `(a + b)` per lane, halved if `HALVE` (`SHADD16` / `SADD16`).
#[inline(always)]
pub fn add<const HALVE: bool>(a: u32, b: u32) -> u32 {
    if HALVE { shadd16(a, b) } else { sadd16(a, b) }
}

/// `(a − b)` per lane, halved if `HALVE`.
#[inline(always)]
pub fn sub<const HALVE: bool>(a: u32, b: u32) -> u32 {
    if HALVE { shsub16(a, b) } else { ssub16(a, b) }
}

/// `a − j·b` as complex lanes (re + b.im, im − b.re), halved if `HALVE`.
#[inline(always)]
pub fn sub_j<const HALVE: bool>(a: u32, b: u32) -> u32 {
    if HALVE { shsax(a, b) } else { ssax(a, b) }
}

/// `a + j·b` as complex lanes (re − b.im, im + b.re), halved if `HALVE`.
#[inline(always)]
pub fn add_j<const HALVE: bool>(a: u32, b: u32) -> u32 {
    if HALVE { shasx(a, b) } else { sasx(a, b) }
}

/// `a · w` for packed Q15 complex values, rounded to nearest; `|a| · |w| < 2³⁰` keeps the
/// products exact. Four instructions.
#[inline(always)]
pub fn rotate(a: u32, w: u32) -> u32 {
    let re = smlsd(a, w, 1 << 14) >> 15;
    let im = smladx(a, w, 1 << 14);
    pkhbt_lsl1(re as u32, im as u32)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn p(lo: i16, hi: i16) -> u32 {
        (lo as u16 as u32) | ((hi as u16 as u32) << 16)
    }

    fn lo_i(x: u32) -> i64 {
        x as u16 as i16 as i64
    }

    fn hi_i(x: u32) -> i64 {
        (x >> 16) as u16 as i16 as i64
    }

    #[test]
    fn lane_semantics() {
        assert_eq!(sadd16(p(1, -2), p(3, 4)), p(4, 2));
        assert_eq!(ssub16(p(1, -2), p(3, 4)), p(-2, -6));
        assert_eq!(shadd16(p(3, -3), p(0, 0)), p(1, -2)); // floor
        assert_eq!(sasx(p(10, 20), p(1, 2)), p(8, 21));
        assert_eq!(ssax(p(10, 20), p(1, 2)), p(12, 19));
        assert_eq!(smlsd(p(3, 4), p(5, 6), 7), 3 * 5 - 4 * 6 + 7);
        assert_eq!(smladx(p(3, 4), p(5, 6), 7), 3 * 6 + 4 * 5 + 7);
        assert_eq!(smuad(p(-3, 4), p(5, 6)), (-15 + 24) as u32);
        assert_eq!(smuad(p(-32768, -32768), p(-32768, -32768)), 1 << 31);
        let big = 1i64 << 40;
        assert_eq!(
            smlsld(p(-32768, 32767), p(-32768, -32768), big),
            big + (1 << 30) + 32767 * 32768
        );
        assert_eq!(smlaldx(p(3, -4), p(5, 6), -big), -big + 3 * 6 - 4 * 5);
        // The dot product equals its element-wise definition, odd lengths included.
        let xs: std::vec::Vec<u32> = (0..7i32)
            .map(|i| p((1000 * i - 3000) as i16, (77 - 20 * i) as i16))
            .collect();
        let ws: std::vec::Vec<u32> = (0..7i32)
            .map(|i| p((-32768 + 9000 * i) as i16, (32767 - i) as i16))
            .collect();
        for len in 0..=7 {
            let (mut re, mut im) = (0i64, 0i64);
            for i in 0..len {
                let (a, b) = (xs[i as usize], ws[i as usize]);
                re += lo_i(a) * lo_i(b) - hi_i(a) * hi_i(b);
                im += lo_i(a) * hi_i(b) + hi_i(a) * lo_i(b);
            }
            assert_eq!(complex_mac(&xs[..len as usize], &ws), (re, im), "len {len}");
        }
        // Widening sums equal their i64 definition at every length, wrapping included.
        for len in 0..=7usize {
            let mut acc: std::vec::Vec<u32> = (0..16u32)
                .map(|i| (i32::MAX as u32 - 3).wrapping_add(i))
                .collect();
            let before = acc.clone();
            widen_add(&mut acc, &xs[..len]);
            for i in 0..8 {
                let add = |part: i64| if i < len { part } else { 0 };
                let want = |b: u32, part: i64| (b as i32 as i64 + add(part)) as i32 as u32;
                assert_eq!(
                    acc[2 * i],
                    want(before[2 * i], lo_i(xs[i.min(6)])),
                    "len {len} re {i}"
                );
                assert_eq!(
                    acc[2 * i + 1],
                    want(before[2 * i + 1], hi_i(xs[i.min(6)])),
                    "len {len} im {i}"
                );
            }
        }
        // (0.5 + 0.25j) · j = −0.25 + 0.5j
        assert_eq!(rotate(p(16384, 8192), p(0, 32767)), p(-8192, 16384));
    }

    #[test]
    fn block_coefficients_multiply_their_own_16_words() {
        let xs: std::vec::Vec<u32> = (0..53i32)
            .map(|i| p((-32768 + 1237 * i) as i16, (32767 - 1201 * i) as i16))
            .collect();
        let cs = [p(-32768, -32768), p(32767, 5), p(-7, 23456), p(100, -100)];
        for len in [0usize, 15, 16, 17, 32, 47, 48, 53] {
            // The widening sums through their 16-word blocks too.
            let mut wide = std::vec![0x7fff_fff0u32; 110];
            widen_add(&mut wide, &xs[..len]);
            for i in 0..55 {
                let (re, im) = if i < len {
                    (lo_i(xs[i]), hi_i(xs[i]))
                } else {
                    (0, 0)
                };
                let want = |part: i64| (0x7fff_fff0u32 as i32 as i64 + part) as i32 as u32;
                assert_eq!(
                    (wide[2 * i], wide[2 * i + 1]),
                    (want(re), want(im)),
                    "len {len} {i}"
                );
            }
            for blocks in 1..=4usize {
                let mut acc = std::vec![0x7fff_fff0u32; 110];
                let before = acc.clone();
                mac_add_blocks(&mut acc, &xs[..len], &cs[..blocks]);
                for i in 0..55 {
                    let (re, im) = if i < len.min(16 * blocks) {
                        let (a, b) = (cs[i / 16], xs[i]);
                        (
                            lo_i(a) * lo_i(b) - hi_i(a) * hi_i(b),
                            lo_i(a) * hi_i(b) + hi_i(a) * lo_i(b),
                        )
                    } else {
                        (0, 0)
                    };
                    let want = |b: u32, part: i64| (b as i32 as i64 + part) as i32 as u32;
                    assert_eq!(
                        acc[2 * i],
                        want(before[2 * i], re),
                        "len {len} blocks {blocks} re {i}"
                    );
                    assert_eq!(
                        acc[2 * i + 1],
                        want(before[2 * i + 1], im),
                        "len {len} blocks {blocks} im {i}"
                    );
                }
            }
        }
    }

    #[test]
    fn multiply_accumulate_sums_equal_their_i64_definition_wrapping_included() {
        let xs: std::vec::Vec<u32> = (0..13i32)
            .map(|i| p((-32768 + 5461 * i) as i16, (32767 - 4099 * i) as i16))
            .collect();
        for c in [p(-32768, -32768), p(32767, -1), p(-12345, 23456), p(0, 0)] {
            for len in 0..=13usize {
                let mut acc: std::vec::Vec<u32> = (0..28u32)
                    .map(|i| (i32::MAX as u32 - 5).wrapping_add(i.wrapping_mul(0x1357_9bdf)))
                    .collect();
                let before = acc.clone();
                mac_add(&mut acc, &xs[..len], c);
                for i in 0..14 {
                    let (re, im) = if i < len {
                        let (a, b) = (c, xs[i]);
                        (
                            lo_i(a) * lo_i(b) - hi_i(a) * hi_i(b),
                            lo_i(a) * hi_i(b) + hi_i(a) * lo_i(b),
                        )
                    } else {
                        (0, 0)
                    };
                    let want = |b: u32, part: i64| (b as i32 as i64 + part) as i32 as u32;
                    assert_eq!(acc[2 * i], want(before[2 * i], re), "len {len} re {i}");
                    assert_eq!(
                        acc[2 * i + 1],
                        want(before[2 * i + 1], im),
                        "len {len} im {i}"
                    );
                }
                // One coefficient per 16 words: the same sums where c is block 0's.
                let mut blocks = before.clone();
                let per_block = [c, p(1, 2), p(-3, 4)];
                mac_add_blocks(&mut blocks, &xs[..len], &per_block[..1]);
                assert_eq!(blocks, acc, "len {len}");
                // Widening sums over the same lengths (two quads and a tail).
                let mut wide = before.clone();
                widen_add(&mut wide, &xs[..len]);
                for i in 0..14 {
                    let (re, im) = if i < len {
                        (lo_i(xs[i]), hi_i(xs[i]))
                    } else {
                        (0, 0)
                    };
                    let want = |b: u32, part: i64| (b as i32 as i64 + part) as i32 as u32;
                    assert_eq!(wide[2 * i], want(before[2 * i], re), "len {len} re {i}");
                    assert_eq!(
                        wide[2 * i + 1],
                        want(before[2 * i + 1], im),
                        "len {len} im {i}"
                    );
                }
            }
        }
    }
}
