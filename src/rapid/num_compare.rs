//! How RAPID compares two nums: the six comparison operators, shared by
//! the walk's evaluation and the interpreter's.

use super::syntax::BinaryOp;

/// A comparison of two nums (`<`, `<=`, `=`, `<>`, `>=`, `>`); `None`
/// for any other operator.
pub(crate) fn compare(op: BinaryOp, a: f64, b: f64) -> Option<bool> {
    use BinaryOp::*;
    Some(match op {
        Lt => a < b,
        Le => a <= b,
        Eq => a == b,
        Ne => a != b,
        Ge => a >= b,
        Gt => a > b,
        _ => return None,
    })
}
