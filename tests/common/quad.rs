//! Gauss-Legendre quadrature for the reference integrals of the tests, computed here
//! (independently of the crate) by Newton's method on the Legendre three-term recurrence.

/// Nodes and weights of the n-point Gauss-Legendre rule on [-1, 1].
pub fn gauss_legendre(n: usize) -> (Vec<f64>, Vec<f64>) {
    let mut x = vec![0.0; n];
    let mut w = vec![0.0; n];
    for i in 0..n {
        let mut z = (std::f64::consts::PI * (i as f64 + 0.75) / (n as f64 + 0.5)).cos();
        // (P_n(z), P_n'(z)) from (k) P_k = (2k - 1) z P_{k-1} - (k - 1) P_{k-2}
        let legendre = |z: f64| {
            let (mut p0, mut p1) = (1.0, z);
            for k in 2..=n {
                let p2 = ((2 * k - 1) as f64 * z * p1 - (k - 1) as f64 * p0) / k as f64;
                p0 = p1;
                p1 = p2;
            }
            (p1, n as f64 * (z * p1 - p0) / (z * z - 1.0))
        };
        for _ in 0..100 {
            let (p, dp) = legendre(z);
            let dz = p / dp;
            z -= dz;
            if dz.abs() < 1e-16 {
                break;
            }
        }
        let (_, dp) = legendre(z);
        x[i] = z;
        w[i] = 2.0 / ((1.0 - z * z) * dp * dp);
    }
    (x, w)
}
