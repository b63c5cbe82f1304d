//! MJCF's orientation forms (`quat`, `axisangle`, `euler`, `xyaxes`, `zaxis`) as MuJoCo's
//! compiler resolves them, as unit quaternions.

use glam::{DQuat, DVec3};

/// How angles in the file are written (`<compiler angle=…>`).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(super) enum Angle {
    Degree,
    Radian,
}

impl Angle {
    pub(super) fn to_radians(self, x: f64) -> f64 {
        match self {
            Angle::Degree => x / 180.0 * core::f64::consts::PI,
            Angle::Radian => x,
        }
    }
}

/// One orientation as written on an element.
#[derive(Clone, Debug, PartialEq)]
pub(super) enum Orientation {
    /// `quat="w x y z"`, normalised by the compiler.
    Quat([f64; 4]),
    /// `axisangle="x y z angle"`.
    AxisAngle([f64; 4]),
    /// `euler="a b c"` in the compiler's sequence.
    Euler([f64; 3]),
    /// `xyaxes="x1 x2 x3 y1 y2 y3"`.
    XyAxes([f64; 6]),
    /// `zaxis="x y z"`: the rotation taking z to this direction by the shortest arc.
    ZAxis([f64; 3]),
}

/// The shortest-arc rotation taking +z to `v` (MuJoCo's `z2quat`): about x by π when `v` is
/// along −z. `v` need not be normalised.
pub(super) fn z_to(v: DVec3) -> DQuat {
    let v = v.normalize_or_zero();
    let cross = DVec3::Z.cross(v);
    let s = cross.length();
    let axis = if s < 1e-10 { DVec3::X } else { cross / s };
    let angle = s.atan2(v.z);
    let (sin, cos) = (angle / 2.0).sin_cos();
    DQuat::from_xyzw(axis.x * sin, axis.y * sin, axis.z * sin, cos)
}

/// A quaternion `w x y z` as written, normalised.
pub(super) fn quat_wxyz(q: [f64; 4]) -> Result<DQuat, &'static str> {
    let q = DQuat::from_xyzw(q[1], q[2], q[3], q[0]);
    let n = q.length();
    if !n.is_finite() || n < 1e-14 {
        return Err("quaternion is zero or not finite");
    }
    Ok(q / n)
}

impl Orientation {
    /// The rotation, with `angle` the compiler's unit and `sequence` its `eulerseq`.
    pub(super) fn resolve(&self, angle: Angle, sequence: &[u8; 3]) -> Result<DQuat, &'static str> {
        match *self {
            Orientation::Quat(q) => quat_wxyz(q),
            Orientation::AxisAngle([x, y, z, a]) => {
                let axis = DVec3::new(x, y, z);
                let n = axis.length();
                if n < 1e-14 {
                    return Err("axisangle too small");
                }
                let half = angle.to_radians(a) / 2.0;
                let (sin, cos) = half.sin_cos();
                let axis = axis / n;
                Ok(DQuat::from_xyzw(
                    axis.x * sin,
                    axis.y * sin,
                    axis.z * sin,
                    cos,
                ))
            }
            Orientation::XyAxes([x1, x2, x3, y1, y2, y3]) => {
                let x = DVec3::new(x1, x2, x3);
                let nx = x.length();
                if nx < 1e-14 {
                    return Err("xaxis too small");
                }
                let x = x / nx;
                let y = DVec3::new(y1, y2, y3);
                let y = y - x * x.dot(y);
                let ny = y.length();
                if ny < 1e-14 {
                    return Err("yaxis too small");
                }
                let y = y / ny;
                let z = x.cross(y);
                let nz = z.length();
                if nz < 1e-14 {
                    return Err("cross(xaxis, yaxis) too small");
                }
                let m = glam::DMat3::from_cols(x, y, z / nz);
                Ok(DQuat::from_mat3(&m).normalize())
            }
            Orientation::ZAxis([x, y, z]) => {
                let v = DVec3::new(x, y, z);
                if v.length() < 1e-14 {
                    return Err("zaxis too small");
                }
                Ok(z_to(v))
            }
            Orientation::Euler(e) => {
                let mut q = DQuat::IDENTITY;
                for (k, &axis) in sequence.iter().enumerate() {
                    let half = angle.to_radians(e[k]) / 2.0;
                    let (sin, cos) = half.sin_cos();
                    let r = match axis.to_ascii_lowercase() {
                        b'x' => DQuat::from_xyzw(sin, 0.0, 0.0, cos),
                        b'y' => DQuat::from_xyzw(0.0, sin, 0.0, cos),
                        b'z' => DQuat::from_xyzw(0.0, 0.0, sin, cos),
                        _ => return Err("euler sequence can only contain x, y, z, X, Y, Z"),
                    };
                    // Lowercase: about the moving axes (post-multiply); uppercase: about the
                    // fixed axes (pre-multiply).
                    q = if axis.is_ascii_lowercase() {
                        q * r
                    } else {
                        r * q
                    };
                }
                Ok(q.normalize())
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn close(a: DQuat, b: DQuat) -> bool {
        // q and −q are the same rotation.
        (a - b).length() < 1e-12 || (a + b).length() < 1e-12
    }

    #[test]
    fn every_form_gives_the_same_quarter_turn_about_z() {
        let want = DQuat::from_rotation_z(core::f64::consts::FRAC_PI_2);
        let xyz = *b"xyz";
        let forms = [
            (Orientation::Quat([1.0, 0.0, 0.0, 1.0]), Angle::Radian),
            (Orientation::AxisAngle([0.0, 0.0, 2.0, 90.0]), Angle::Degree),
            (
                Orientation::AxisAngle([0.0, 0.0, 1.0, core::f64::consts::FRAC_PI_2]),
                Angle::Radian,
            ),
            (Orientation::Euler([0.0, 0.0, 90.0]), Angle::Degree),
            (
                Orientation::XyAxes([0.0, 1.0, 0.0, -1.0, 0.5, 0.0]),
                Angle::Radian,
            ),
        ];
        for (form, unit) in forms {
            assert!(close(form.resolve(unit, &xyz).unwrap(), want), "{form:?}");
        }
    }

    #[test]
    fn euler_sequences_moving_and_fixed() {
        let (a, b) = (0.3, -0.8);
        let (rx, ry) = (DQuat::from_rotation_x(a), DQuat::from_rotation_y(b));
        // Intrinsic x then y: Rx·Ry. Extrinsic X then Y: Ry·Rx.
        let moving = Orientation::Euler([a, b, 0.0])
            .resolve(Angle::Radian, b"xyz")
            .unwrap();
        assert!(close(moving, rx * ry));
        let fixed = Orientation::Euler([a, b, 0.0])
            .resolve(Angle::Radian, b"XYZ")
            .unwrap();
        assert!(close(fixed, ry * rx));
        assert!(
            Orientation::Euler([a, b, 0.0])
                .resolve(Angle::Radian, b"xqz")
                .is_err()
        );
    }

    #[test]
    fn zaxis_takes_z_to_the_direction() {
        for v in [
            DVec3::new(1.0, 2.0, -0.5),
            DVec3::Z,
            -DVec3::Z,
            DVec3::new(0.0, 0.0, -3.0),
        ] {
            let q = Orientation::ZAxis(v.to_array())
                .resolve(Angle::Radian, b"xyz")
                .unwrap();
            assert!((q * DVec3::Z - v.normalize()).length() < 1e-12, "{v}");
        }
        assert!(
            Orientation::ZAxis([0.0; 3])
                .resolve(Angle::Radian, b"xyz")
                .is_err()
        );
        assert!(quat_wxyz([0.0; 4]).is_err());
    }
}
