//! The error statistics of one run's hits against a reference run on the same rays: the
//! table of `smoothtri precision` (the demo) and `smoothtri.precision_sweep` (the Python
//! package), computed once here so that both give the same numbers bit for bit.

use glam::DVec3;

/// One ray's hit as the precision study keeps it, widened to `f64`: `(t, point, t_error)`,
/// `t` and `t_error` in units of the ray's direction, the point in the mesh's units.
pub type Traced = (f64, DVec3, f64);

/// The error statistics of a run against a reference ([`error_stats`]). Errors are relative
/// to a length the caller gives (the demo and the Python package: the mesh's bounding-box
/// diagonal).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ErrorStats {
    /// Hits compared: rays that hit in both the run and the reference.
    pub hits: usize,
    /// The largest relative hit-point error, `|point − point_ref| / diag`; 0 without hits.
    pub max: f64,
    /// The 99.9th percentile of the relative hit-point errors ([`percentile`] at 0.999); 0
    /// without hits.
    pub p999: f64,
    /// The mean relative hit-point error (summed in ray order); 0 without hits.
    pub mean: f64,
    /// The mean returned `t_error / diag` (relative to `diag` for rays of unit direction); 0
    /// without hits.
    pub mean_t_error: f64,
    /// The share (0 to 1) of the compared hits whose `|t − t_ref|` is at most their
    /// `t_error`; 0 without hits.
    pub bound_holds: f64,
    /// Rays that hit in one run and miss in the other.
    pub disagreements: usize,
}

/// The `q`-quantile (`q` in `[0, 1]`) of values sorted in ascending order: the element at
/// the 1-based rank `⌈q·n⌉` (clamped to `1..=n`); 0 when `sorted` is empty.
///
/// # Panics
/// Never.
pub fn percentile(sorted: &[f64], q: f64) -> f64 {
    if sorted.is_empty() {
        return 0.0;
    }
    let k = ((q * sorted.len() as f64).ceil() as usize).clamp(1, sorted.len()) - 1;
    sorted.get(k).copied().unwrap_or(0.0)
}

/// The statistics of `run` (per ray: its hit or `None`) against `reference` (per ray: the
/// reference hit's `(t, point)` or `None`), ray `i` of one paired with ray `i` of the other
/// (the longer one's extra rays are ignored). Point errors and `t_error`s are divided by
/// `diag` (a positive length in the mesh's units; the callers pass the bounding-box
/// diagonal).
///
/// # Panics
/// Never.
pub fn error_stats(
    run: &[Option<Traced>],
    reference: &[Option<(f64, DVec3)>],
    diag: f64,
) -> ErrorStats {
    let mut errs = Vec::new();
    let mut terr = 0.0;
    let mut holds = 0usize;
    let mut dis = 0usize;
    for (r, q) in run.iter().zip(reference) {
        match (r, q) {
            (Some((t, p, te)), Some((qt, qp))) => {
                errs.push((*p - *qp).length() / diag);
                terr += te / diag;
                if (t - qt).abs() <= *te {
                    holds += 1;
                }
            }
            (None, None) => {}
            _ => dis += 1,
        }
    }
    let hits = errs.len();
    let mean = errs.iter().sum::<f64>() / hits.max(1) as f64;
    errs.sort_by(f64::total_cmp);
    ErrorStats {
        hits,
        max: errs.last().copied().unwrap_or(0.0),
        p999: percentile(&errs, 0.999),
        mean,
        mean_t_error: terr / hits.max(1) as f64,
        bound_holds: holds as f64 / hits.max(1) as f64,
        disagreements: dis,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn percentile_is_the_element_at_rank_ceil_q_n() {
        let v: Vec<f64> = (1..=10).map(f64::from).collect();
        assert_eq!(percentile(&v, 0.999), 10.0);
        assert_eq!(percentile(&v, 0.5), 5.0);
        assert_eq!(percentile(&v, 0.51), 6.0);
        assert_eq!(percentile(&v, 0.0), 1.0);
        assert_eq!(percentile(&[], 0.5), 0.0);
    }

    #[test]
    fn four_hits_against_a_reference() {
        let x = |v: f64| DVec3::new(v, 0.0, 0.0);
        // Six rays, diagonal 2: four compared hits with point errors 0.5, 0.1, 0.3, 0.0
        // (relative: 0.25, 0.05, 0.15, 0), one hit the reference misses, one miss the
        // reference hits.
        let run = [
            Some((1.0, x(1.0), 0.2)),  // |Δt| 0.1 <= 0.2: holds
            Some((2.0, x(2.2), 0.05)), // |Δt| 0.1 > 0.05
            Some((3.0, x(3.3), 0.4)),  // |Δt| 0 <= 0.4: holds
            Some((4.0, x(4.0), 0.0)),  // |Δt| 0 <= 0: holds
            Some((5.0, x(5.0), 0.0)),
            None,
        ];
        let reference = [
            Some((1.1, x(0.5))),
            Some((2.1, x(2.3))),
            Some((3.0, x(3.0))),
            Some((4.0, x(4.0))),
            None,
            Some((6.0, x(6.0))),
        ];
        let s = error_stats(&run, &reference, 2.0);
        assert_eq!(s.hits, 4);
        assert_eq!(s.disagreements, 2);
        assert_eq!(s.max, 0.25);
        // Rank ⌈0.999 · 4⌉ = 4 of the sorted errors: the largest.
        assert_eq!(s.p999, 0.25);
        let mean = (0.25 + (2.2f64 - 2.3).abs() / 2.0 + (3.3f64 - 3.0) / 2.0 + 0.0) / 4.0;
        assert_eq!(s.mean, mean);
        assert!((s.mean - 0.1125).abs() < 1e-12);
        assert_eq!(s.mean_t_error, (0.1 + 0.025 + 0.2 + 0.0) / 4.0);
        assert_eq!(s.bound_holds, 0.75);
    }

    #[test]
    fn no_hits_give_zeros() {
        let s = error_stats(&[None, Some((1.0, DVec3::ZERO, 0.0))], &[None, None], 1.0);
        assert_eq!(
            s,
            ErrorStats {
                hits: 0,
                max: 0.0,
                p999: 0.0,
                mean: 0.0,
                mean_t_error: 0.0,
                bound_holds: 0.0,
                disagreements: 1,
            }
        );
    }
}
