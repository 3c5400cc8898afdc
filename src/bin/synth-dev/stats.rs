//! The summary of repeated measurements every benchmark table shows.
//!
//! In: the measurements (seconds, milliseconds). Out: their least, mean, median and greatest.

/// Least, mean, median and greatest of some measurements.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Stats {
    /// The least value.
    pub min: f64,
    /// The arithmetic mean.
    pub mean: f64,
    /// The middle value; for an even count, the mean of the two middle values.
    pub median: f64,
    /// The greatest value.
    pub max: f64,
}

impl Stats {
    /// The summary of `values`; `None` when there are none.
    pub fn of(values: &[f64]) -> Option<Stats> {
        let mut xs = values.to_vec();
        xs.sort_by(f64::total_cmp);
        let n = xs.len();
        let (&min, &max) = (xs.first()?, xs.last()?);
        let median = match n % 2 {
            1 => xs[n / 2],
            _ => (xs[n / 2 - 1] + xs[n / 2]) / 2.0,
        };
        Some(Stats {
            min,
            mean: xs.iter().sum::<f64>() / n as f64,
            median,
            max,
        })
    }
}
