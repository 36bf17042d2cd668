//! The built-in hold-out of `rotorid identify LOG...` without `--verify`: part of the data is
//! kept back for verification, so that the scores measure prediction on data the models did
//! not learn from, not the fit.
//!
//! The held-out part is later in time than most of the training data (a model flown after
//! it was learnt sees later data): with several segments, the whole segment whose length is
//! closest to the wanted fraction (the later one of equals); with one, or when no segment is
//! small enough, the last part of the longest segment.

use rotorid_sim::plant::SensorSample;

/// A segment of a log, with where it came from.
#[derive(Debug, Clone)]
pub struct Labelled {
    /// The log file.
    pub file: String,
    /// 1-based segment number within its log.
    pub segment: usize,
    /// The samples.
    pub samples: Vec<SensorSample>,
}

/// Training and verification data, and how they were split.
#[derive(Debug, Clone)]
pub struct Split {
    /// Training segments, in log order.
    pub training: Vec<Vec<SensorSample>>,
    /// The verification stretch.
    pub verification: Vec<SensorSample>,
    /// How, in a sentence.
    pub how: String,
}

/// Why the data could not be split.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[non_exhaustive]
pub enum SplitError {
    /// The fraction is not in (0, 1).
    #[error("--holdout must be in (0, 1), got {0}")]
    Fraction(f64),
    /// Too little data to keep any back.
    #[error("{samples} usable samples are too few to hold {fraction:.0} % out for verification (each part needs at least {min}): give a separate --verify log")]
    TooShort {
        /// Usable samples.
        samples: usize,
        /// The wanted fraction (%).
        fraction: f64,
        /// The least samples of each part.
        min: usize,
    },
}

fn span(s: &[SensorSample]) -> (f64, f64) {
    (
        s.first().map_or(0.0, |x| x.t),
        s.last().map_or(0.0, |x| x.t),
    )
}

/// Splits `segments` (every usable segment of every log, in order) holding out about
/// `fraction` of the samples for verification; each part has at least `min` samples
/// ([`crate::import::min_useful_samples`]).
pub fn split(segments: Vec<Labelled>, fraction: f64, min: usize) -> Result<Split, SplitError> {
    if !(fraction > 0.0 && fraction < 1.0) {
        return Err(SplitError::Fraction(fraction));
    }
    let total: usize = segments.iter().map(|s| s.samples.len()).sum();
    let target = fraction * total as f64;
    let too_short = SplitError::TooShort {
        samples: total,
        fraction: fraction * 100.0,
        min,
    };
    // A whole segment, when one is about the wanted size and leaves enough to train on.
    let whole = segments
        .iter()
        .enumerate()
        .filter(|(_, s)| {
            let n = s.samples.len();
            n >= min && total - n >= min && (n as f64) <= 2.0 * target && (n as f64) >= 0.5 * target
        })
        .min_by(|(i, a), (j, b)| {
            let da = (a.samples.len() as f64 - target).abs();
            let db = (b.samples.len() as f64 - target).abs();
            da.total_cmp(&db).then(j.cmp(i))
        })
        .map(|(i, _)| i);
    if let Some(k) = whole {
        let mut segments = segments;
        let held = segments.remove(k);
        let (a, b) = span(&held.samples);
        let n = held.samples.len();
        return Ok(Split {
            how: format!(
                "held out for verification: segment {} of {} ({a:.2}–{b:.2} s, {n} samples, {:.0} % of the data); trained on the other {} segment(s)",
                held.segment,
                held.file,
                100.0 * n as f64 / total as f64,
                segments.len()
            ),
            training: segments.into_iter().map(|s| s.samples).collect(),
            verification: held.samples,
        });
    }
    // Else the last part of the longest segment.
    let Some(k) = segments
        .iter()
        .enumerate()
        .rev()
        .max_by_key(|(_, s)| s.samples.len())
        .map(|(i, _)| i)
    else {
        return Err(too_short);
    };
    let mut segments = segments;
    let longest = &segments[k];
    let n = longest.samples.len();
    let held_n = ((n as f64) * fraction.min(target / n as f64)).round() as usize;
    let held_n = held_n.max(min);
    if held_n >= n || n - held_n < min {
        return Err(too_short);
    }
    let held = segments[k].samples.split_off(n - held_n);
    let (a, b) = span(&held);
    let how = format!(
        "held out for verification: the last {held_n} samples of segment {} of {} ({a:.2}–{b:.2} s, {:.0} % of the data); trained on the rest",
        segments[k].segment,
        segments[k].file,
        100.0 * held_n as f64 / total as f64
    );
    Ok(Split {
        training: segments
            .into_iter()
            .map(|s| s.samples)
            .filter(|s| s.len() > 1)
            .collect(),
        verification: held,
        how,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    fn seg(file: &str, segment: usize, n: usize, t0: f64) -> Labelled {
        Labelled {
            file: file.into(),
            segment,
            samples: (0..n)
                .map(|k| SensorSample {
                    t: t0 + k as f64 * 0.02,
                    ..SensorSample::default()
                })
                .collect(),
        }
    }

    #[test]
    fn one_segment_keeps_its_end_back() {
        let s = split(vec![seg("a.ulg", 1, 1000, 0.0)], 0.3, 100).unwrap();
        assert_eq!(s.verification.len(), 300);
        assert_eq!(s.training.len(), 1);
        assert_eq!(s.training[0].len(), 700);
        // Verification comes after training in time.
        assert!(s.verification[0].t > s.training[0].last().unwrap().t);
        assert!(s.how.contains("the last 300 samples"), "{}", s.how);
    }

    #[test]
    fn a_segment_of_about_the_wanted_size_is_held_out_whole() {
        let s = split(
            vec![
                seg("a.ulg", 1, 700, 0.0),
                seg("a.ulg", 2, 290, 20.0),
                seg("b.ulg", 1, 300, 40.0),
            ],
            0.25,
            100,
        )
        .unwrap();
        // Target 322 samples: 300 (b.ulg segment 1) is closest.
        assert_eq!(s.verification.len(), 300);
        assert_eq!(s.training.len(), 2);
        assert!(s.how.contains("segment 1 of b.ulg"), "{}", s.how);
    }

    #[test]
    fn too_little_data_and_bad_fractions_are_errors() {
        assert!(matches!(
            split(vec![seg("a.ulg", 1, 150, 0.0)], 0.3, 100),
            Err(SplitError::TooShort { .. })
        ));
        assert_eq!(
            split(vec![seg("a.ulg", 1, 1000, 0.0)], 1.0, 100).unwrap_err(),
            SplitError::Fraction(1.0)
        );
        assert!(matches!(
            split(Vec::new(), 0.3, 100),
            Err(SplitError::TooShort { .. })
        ));
    }
}
