//! NuSMV 2.5.4's integer arithmetic: the one every in-process evaluation of a plant uses (the
//! explicit semantics of [`explicit`](super::explicit), the parser's reachability search, the
//! SAT encoding of the closed loop).
//!
//! In: integers of the plant (always within NuSMV's range, a C `int`: the parser refuses a
//! larger literal, as NuSMV's lexer does with "illegal integer") and an operator. Out: the
//! value NuSMV computes, or `None` for a division or `mod` by zero, which NuSMV reports as an
//! error.
//!
//! NuSMV computes in C `int`s: 32 bits, two's complement, and a result that leaves the range
//! wraps around (`2147483647 + 1` is `-2147483648`, `65536 * 65536` is `0`, `-x` of
//! `-2147483648` is itself). `/` truncates toward zero and `mod` takes the sign of the dividend,
//! as C's `/` and `%` do (`-7 / 2 = -3`, `-7 mod 2 = -1`, `7 mod -2 = 1`), and
//! `-2147483648 / -1` is `-2147483648`, `mod -1` of it `0`. All of this was measured on NuSMV
//! 2.5.4, on constants and on variables alike (the tests below keep the figures).
//!
//! Evaluating exactly as NuSMV does, rather than refusing the plant line whose arithmetic can
//! leave the 32-bit range, is what keeps the in-process verdicts NuSMV's: the wrap is fully
//! determined, so the same state gives the same value in both. A refusal would need a range
//! analysis of every expression, and any such analysis either refuses plants NuSMV checks
//! without complaint (a product whose large operands never meet on any state) or lets some
//! overflow through.

use super::BinOp;

/// `x op y` for an arithmetic operator (`+`, `-`, `*`, `/`, `mod`) as NuSMV computes it;
/// `None` for a division or `mod` by zero, and for an operator that is not arithmetic.
pub(crate) fn arithmetic(op: BinOp, x: i64, y: i64) -> Option<i64> {
    let (a, b) = (c_int(x), c_int(y));
    let r = match op {
        BinOp::Add => a.wrapping_add(b),
        BinOp::Sub => a.wrapping_sub(b),
        BinOp::Mul => a.wrapping_mul(b),
        // Rust's `/` and `%` on `i32` truncate like C's; only `MIN / -1` needs the wrap.
        BinOp::Div if b != 0 => a.wrapping_div(b),
        BinOp::Mod if b != 0 => a.wrapping_rem(b),
        _ => return None,
    };
    Some(i64::from(r))
}

/// Unary minus as NuSMV computes it (`-(-2147483648)` wraps to itself).
pub(crate) fn negate(x: i64) -> i64 {
    i64::from(c_int(x).wrapping_neg())
}

/// A plant integer as the C `int` NuSMV holds it. Every integer of a plant is in range (the
/// parser and these operations see to it), so this conversion never changes a value.
fn c_int(x: i64) -> i32 {
    x as i32
}

#[cfg(test)]
mod tests {
    use super::*;

    const MIN: i64 = i32::MIN as i64;
    const MAX: i64 = i32::MAX as i64;

    /// NuSMV 2.5.4's answers, read from its traces and invariants.
    #[test]
    fn arithmetic_is_nusmv_s() {
        use BinOp::*;
        let cases = [
            (Add, MAX, 1, MIN),
            (Mul, 65536, 65536, 0),
            (Mul, 46341, 46341, -2147479015),
            (Sub, -MAX, 2, MAX),
            (Div, -7, 2, -3),
            (Mod, -7, 2, -1),
            (Div, 7, -2, -3),
            (Mod, 7, -2, 1),
            (Div, -7, -2, 3),
            (Mod, -7, -2, -1),
            (Div, 7, 2, 3),
            (Mod, 7, 2, 1),
            (Div, MIN, -1, MIN),
            (Mod, MIN, -1, 0),
            (Mul, MAX, -3, -2147483645),
            (Add, -MAX, -65536, 2147418113),
        ];
        for (op, x, y, want) in cases {
            assert_eq!(arithmetic(op, x, y), Some(want), "{x} {op:?} {y}");
        }
        assert_eq!(negate(MIN), MIN);
        assert_eq!(negate(-MAX), MAX);
        assert_eq!(arithmetic(Div, 3, 0), None);
        assert_eq!(arithmetic(Mod, 3, 0), None);
        assert_eq!(arithmetic(Lt, 3, 4), None);
    }
}
