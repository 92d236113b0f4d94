//! The lab's one dense solver: linear least squares (the starting levels of
//! the base model, the regressions of the candidates' starts, the static
//! curves) and the damped normal equations of Levenberg–Marquardt: both
//! symmetric positive definite systems, solved by `nalgebra`'s Cholesky
//! decomposition.

use nalgebra::{DMatrix, DVector};

/// Solves `a·x = b` for a symmetric positive definite `a` (given by rows;
/// its lower triangle is read); `None` when `a` is not positive definite,
/// the shapes disagree or the solution is not finite.
pub fn solve_spd(a: &[Vec<f64>], b: &[f64]) -> Option<Vec<f64>> {
    let n = b.len();
    if n == 0 || a.len() != n || a.iter().any(|row| row.len() != n) {
        return None;
    }
    let m = DMatrix::from_fn(n, n, |i, j| a[i][j]);
    let x = m.cholesky()?.solve(&DVector::from_column_slice(b));
    x.iter()
        .all(|v| v.is_finite())
        .then(|| x.as_slice().to_vec())
}

/// Linear least squares `min |A·c − b|` with the columns `cols` of `A`
/// (normal equations `AᵀA·c = Aᵀb`; the problems here have 2–4 columns of
/// comparable scale); `None` when the columns are dependent, the lengths
/// disagree or the solution is not finite.
pub fn lstsq(cols: &[Vec<f64>], b: &[f64]) -> Option<Vec<f64>> {
    if cols.iter().any(|c| c.len() != b.len()) {
        return None;
    }
    let (ata, atb) = normal_equations(cols, b);
    solve_spd(&ata, &atb)
}

/// The normal equations of the columns `cols` of `A` against `b`: `AᵀA`
/// (by rows, symmetric) and `Aᵀb`, each entry summed in sample order as
/// `Iterator::sum` does (the same bits as the plain sums). Levenberg–Marquardt
/// forms them at every iteration over the whole training set.
pub fn normal_equations(cols: &[Vec<f64>], b: &[f64]) -> (Vec<Vec<f64>>, Vec<f64>) {
    let n = cols.len();
    let mut ata = vec![vec![0.0; n]; n];
    let mut atb = vec![0.0; n];
    for r in 0..n {
        let others: Vec<&[f64]> = cols[r..].iter().map(Vec::as_slice).chain([b]).collect();
        let sums = dots(&cols[r], &others);
        for (c, &s) in (r..n).zip(&sums) {
            ata[r][c] = s;
            ata[c][r] = s;
        }
        atb[r] = sums[n - r];
    }
    (ata, atb)
}

/// The dot products of `x` with each of `ys` (over the shortest length,
/// as `zip` does), each summed in order from −0.0 as `Iterator::sum` does
/// (the same bits), four at a time so that their additions overlap.
fn dots(x: &[f64], ys: &[&[f64]]) -> Vec<f64> {
    let len = ys.iter().map(|y| y.len()).fold(x.len(), usize::min);
    let x = &x[..len];
    let mut out = Vec::with_capacity(ys.len());
    let mut groups = ys.chunks_exact(4);
    for y in &mut groups {
        let (y0, y1, y2, y3) = (&y[0][..len], &y[1][..len], &y[2][..len], &y[3][..len]);
        let (mut s0, mut s1, mut s2, mut s3) = (-0.0f64, -0.0f64, -0.0f64, -0.0f64);
        for (i, &xi) in x.iter().enumerate() {
            s0 += xi * y0[i];
            s1 += xi * y1[i];
            s2 += xi * y2[i];
            s3 += xi * y3[i];
        }
        out.extend([s0, s1, s2, s3]);
    }
    for y in groups.remainder() {
        out.push(x.iter().zip(*y).map(|(a, b)| a * b).sum());
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    /// An exact line through three points is recovered, and dependent
    /// columns are refused rather than answered.
    #[test]
    fn least_squares_recovers_a_line_and_refuses_dependent_columns() {
        let x = [0.0, 1.0, 2.0, 3.0];
        let y: Vec<f64> = x.iter().map(|x| 2.0 - 0.5 * x).collect();
        let c = lstsq(&[vec![1.0; 4], x.to_vec()], &y).expect("full rank");
        assert!(
            (c[0] - 2.0).abs() < 1e-12 && (c[1] + 0.5).abs() < 1e-12,
            "{c:?}"
        );
        assert!(lstsq(&[x.to_vec(), x.iter().map(|v| 2.0 * v).collect()], &y).is_none());
        assert!(lstsq(&[vec![1.0; 3]], &y).is_none());
        assert!(solve_spd(&[vec![0.0, 0.0], vec![0.0, 0.0]], &[1.0, 1.0]).is_none());
        assert!(solve_spd(&[vec![1.0, 2.0], vec![2.0, 1.0]], &[1.0, 1.0]).is_none());
    }

    /// `dots` is `Iterator::sum` of the products to the last bit, for
    /// every group size (four at a time and the rest), and keeps the
    /// sign of an all-negative-zero sum.
    #[test]
    fn dots_are_the_sums_to_the_last_bit() {
        let n = 1001;
        let series = |k: usize| -> Vec<f64> {
            (0..n)
                .map(|i| ((i * (k + 3)) as f64 * 0.37).sin() * 10f64.powi(i as i32 % 7 - 3))
                .collect()
        };
        let x = series(0);
        for count in 1..=9 {
            let ys: Vec<Vec<f64>> = (1..=count).map(series).collect();
            let refs: Vec<&[f64]> = ys.iter().map(Vec::as_slice).collect();
            let got = dots(&x, &refs);
            assert_eq!(got.len(), count);
            for (y, g) in ys.iter().zip(&got) {
                let want: f64 = x.iter().zip(y).map(|(a, b)| a * b).sum();
                assert_eq!(g.to_bits(), want.to_bits(), "{count} series: {g} vs {want}");
            }
        }
        // Unequal lengths: over the shortest, as `zip`.
        let (short, long) = (series(1), series(2));
        let got = dots(&short[..10], &[&long, &long, &long, &long, &long[..7]]);
        let want = |m: usize| -> f64 { short[..m].iter().zip(&long).map(|(a, b)| a * b).sum() };
        assert_eq!(got[0].to_bits(), want(7).to_bits());
        assert_eq!(got[4].to_bits(), want(7).to_bits());
        let zeros = vec![-0.0; 8];
        let neg: Vec<&[f64]> = vec![&zeros; 5];
        let positive = vec![1.0; 8];
        let want: f64 = positive.iter().zip(&zeros).map(|(a, b)| a * b).sum();
        for d in dots(&positive, &neg) {
            assert_eq!(d.to_bits(), want.to_bits());
            assert!(d == 0.0 && d.is_sign_negative());
        }
    }
}
