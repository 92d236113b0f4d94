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
    let dot = |x: &[f64], y: &[f64]| x.iter().zip(y).map(|(p, q)| p * q).sum::<f64>();
    let ata: Vec<Vec<f64>> = cols
        .iter()
        .map(|ci| cols.iter().map(|cj| dot(ci, cj)).collect())
        .collect();
    let atb: Vec<f64> = cols.iter().map(|c| dot(c, b)).collect();
    solve_spd(&ata, &atb)
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
}
