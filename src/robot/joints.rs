//! Joint angles, the one currency of every arm: what IK answers, FK and
//! robconf read, and the limits hold.

/// Joint angles of axes 1..6 in radians, ABB sign convention.
pub type Joints = [f64; 6];
