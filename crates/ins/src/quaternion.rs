//! The few quaternion operations the strapdown loop needs, on plain arrays
//! so that the loop stays free of allocation and generic overhead.

/// A unit quaternion [w, x, y, z] rotating the sensor's axes into the
/// local-level frame: v_level = q ⊗ v_body ⊗ q*.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Quat(pub [f64; 4]);

impl Quat {
    /// No rotation.
    pub const IDENTITY: Quat = Quat([1.0, 0.0, 0.0, 0.0]);

    /// The rotation of a rotation vector φ (radians), by the series of
    /// cos(|φ|/2) and sin(|φ|/2)/|φ| to |φ|⁴: exact to 1e-15 for the
    /// increments of one sample (|φ| < 0.01 rad), without trigonometry.
    #[inline]
    pub fn from_rotation_vector(p: [f64; 3]) -> Quat {
        let s = p[0] * p[0] + p[1] * p[1] + p[2] * p[2];
        if s > 1e-4 {
            let a = s.sqrt();
            let k = (0.5 * a).sin() / a;
            return Quat([(0.5 * a).cos(), k * p[0], k * p[1], k * p[2]]);
        }
        let w = 1.0 - s / 8.0 + s * s / 384.0;
        let k = 0.5 - s / 48.0 + s * s / 3840.0;
        Quat([w, k * p[0], k * p[1], k * p[2]])
    }

    /// The Hamilton product self ⊗ r.
    #[inline]
    pub fn compose(self, r: Quat) -> Quat {
        let [a, b, c, d] = self.0;
        let [e, f, g, h] = r.0;
        Quat([
            a * e - b * f - c * g - d * h,
            a * f + b * e + c * h - d * g,
            a * g - b * h + c * e + d * f,
            a * h + b * g - c * f + d * e,
        ])
    }

    /// The inverse rotation.
    #[inline]
    pub fn conj(self) -> Quat {
        let [w, x, y, z] = self.0;
        Quat([w, -x, -y, -z])
    }

    /// Back to unit length (the products drift by rounding).
    #[inline]
    pub fn normalized(self) -> Quat {
        let [w, x, y, z] = self.0;
        let n = 1.0 / (w * w + x * x + y * y + z * z).sqrt();
        Quat([w * n, x * n, y * n, z * n])
    }

    /// q ⊗ v ⊗ q*, in the form with two cross products.
    #[inline]
    pub fn rotate(self, v: [f64; 3]) -> [f64; 3] {
        let [w, x, y, z] = self.0;
        let u = [x, y, z];
        let t = cross(u, v).map(|c| 2.0 * c);
        let ut = cross(u, t);
        [
            v[0] + w * t[0] + ut[0],
            v[1] + w * t[1] + ut[1],
            v[2] + w * t[2] + ut[2],
        ]
    }

    /// The rotation vector of this rotation (angle ≤ π), radians.
    pub fn rotation_vector(self) -> [f64; 3] {
        let [mut w, mut x, mut y, mut z] = self.0;
        if w < 0.0 {
            (w, x, y, z) = (-w, -x, -y, -z);
        }
        let s = (x * x + y * y + z * z).sqrt();
        if s < 1e-300 {
            return [0.0; 3];
        }
        let k = 2.0 * s.atan2(w) / s;
        [k * x, k * y, k * z]
    }

    /// The rotation of a row-major direction cosine matrix (Shepperd's
    /// method, branch on the largest diagonal term for accuracy).
    pub fn from_matrix(m: [[f64; 3]; 3]) -> Quat {
        let tr = m[0][0] + m[1][1] + m[2][2];
        let q = if tr > 0.0 {
            let s = 2.0 * (tr + 1.0).sqrt();
            [
                0.25 * s,
                (m[2][1] - m[1][2]) / s,
                (m[0][2] - m[2][0]) / s,
                (m[1][0] - m[0][1]) / s,
            ]
        } else if m[0][0] > m[1][1] && m[0][0] > m[2][2] {
            let s = 2.0 * (1.0 + m[0][0] - m[1][1] - m[2][2]).sqrt();
            [
                (m[2][1] - m[1][2]) / s,
                0.25 * s,
                (m[0][1] + m[1][0]) / s,
                (m[0][2] + m[2][0]) / s,
            ]
        } else if m[1][1] > m[2][2] {
            let s = 2.0 * (1.0 + m[1][1] - m[0][0] - m[2][2]).sqrt();
            [
                (m[0][2] - m[2][0]) / s,
                (m[0][1] + m[1][0]) / s,
                0.25 * s,
                (m[1][2] + m[2][1]) / s,
            ]
        } else {
            let s = 2.0 * (1.0 + m[2][2] - m[0][0] - m[1][1]).sqrt();
            [
                (m[1][0] - m[0][1]) / s,
                (m[0][2] + m[2][0]) / s,
                (m[1][2] + m[2][1]) / s,
                0.25 * s,
            ]
        };
        Quat(q).normalized()
    }
}

/// The cross product a × b.
#[inline]
pub fn cross(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    [
        a[1] * b[2] - a[2] * b[1],
        a[2] * b[0] - a[0] * b[2],
        a[0] * b[1] - a[1] * b[0],
    ]
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn series_and_matrix_agree_with_the_closed_forms() {
        let p: [f64; 3] = [3e-3, -2e-3, 5e-3];
        let a = (p[0] * p[0] + p[1] * p[1] + p[2] * p[2]).sqrt();
        let q = Quat::from_rotation_vector(p);
        assert!((q.0[0] - (0.5 * a).cos()).abs() < 1e-15);
        assert!((q.0[1] - (0.5 * a).sin() / a * p[0]).abs() < 1e-15);
        let r = q.rotation_vector();
        for k in 0..3 {
            assert!((r[k] - p[k]).abs() < 1e-15);
        }
        // 90° about z takes x to y.
        let q = Quat::from_rotation_vector([0.0, 0.0, std::f64::consts::FRAC_PI_2]);
        let v = q.rotate([1.0, 0.0, 0.0]);
        assert!(v[0].abs() < 1e-15 && (v[1] - 1.0).abs() < 1e-15);
        let m = earth::body_to_level(0.3, -0.2, 1.1);
        let q = Quat::from_matrix(m);
        for j in 0..3 {
            let mut e = [0.0; 3];
            e[j] = 1.0;
            let col = q.rotate(e);
            for i in 0..3 {
                assert!((col[i] - m[i][j]).abs() < 1e-14);
            }
        }
    }
}
