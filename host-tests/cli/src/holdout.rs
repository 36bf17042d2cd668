//! The built-in hold-out of `rotorid identify LOG...` without `--verify`: part of the data is
//! kept back for verification, so that the scores measure prediction on data the models did
//! not learn from, not the fit.
//!
//! The held-out part is later in time than most of the training data (a model flown after
//! it was learnt sees later data): with several segments, the whole segment whose length is
//! closest to the wanted fraction (the later one of equals); with one, or when no segment is
//! small enough, the last part of the longest segment.
//!
//! Unless that takes a stick's excitation with it. An identification log often moves one
//! stick after another (a sweep or doublets per axis, as the simulator's identification flight
//! and ArduPilot's SystemID mode do), and its last part is then the last stick's whole
//! excitation: trained without it, that axis's control power is not determined, and the
//! verdict would blame the flight for a stick it did move. So every stick the log moves
//! (standard deviation over all the usable data at least [`MIN_STICK_STD`]) must keep at least
//! [`KEEP_EXCITATION`] of its standard deviation in the training data. When the usual choice
//! does not, the held-out part is the first in the usual order that does: another whole
//! segment (the closest to the wanted size first), else a stretch of the same length at one of
//! [`OFFSETS`] evenly spaced places in the longest segment, the latest first (the training data
//! are then the parts before and after it). So the held-out part stays as late as it can,
//! and keeps what excitation the training data can spare: a search for the stretch that
//! keeps the most would pick the quietest, where holding the measured state is hard to beat
//! and the scores say little. When none keeps enough, the one that keeps the most. The
//! split's sentence says which stick moved it.

use rotorid_sim::plant::SensorSample;

use crate::verdict::{stick_stds, MIN_STICK_STD, STICK_NAMES};

/// Fraction of a moved stick's standard deviation (over all the usable data) that the training
/// data must keep (see the [module docs](self)). A control derivative's standard error goes
/// as `1/(σ √N)`: half the deviation on 70 % of the samples makes it about 2.4 times the
/// whole log's, where the last stick's sweep held out whole leaves it undetermined.
pub const KEEP_EXCITATION: f64 = 0.5;

/// Places tried in the longest segment for a held-out stretch when the usual choice takes a
/// stick's excitation (see the [module docs](self)): every 5 % of the segment.
pub const OFFSETS: usize = 20;

/// How much of the moved sticks' excitation training on `training` keeps of the whole
/// log's (`whole`: [`stick_stds`] of every sample): the least kept fraction of a moved
/// stick's standard deviation and that stick (`(1, None)` when no stick moved).
fn kept<'a>(
    whole: &[f64],
    training: impl Iterator<Item = &'a SensorSample> + Clone,
) -> (f64, Option<usize>) {
    let training = stick_stds(training);
    (0..whole.len())
        .filter(|&k| whole[k] >= MIN_STICK_STD)
        .map(|k| (training.get(k).copied().unwrap_or(0.0) / whole[k], Some(k)))
        .fold((1.0, None), |best, c| if c.0 < best.0 { c } else { best })
}

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

/// A held-out part: a whole segment, or `len` samples of a segment from `start` on.
#[derive(Debug, Clone, Copy, PartialEq)]
enum Held {
    Whole(usize),
    Stretch {
        segment: usize,
        start: usize,
        len: usize,
    },
}

impl Held {
    /// The samples of `segments` it leaves to train on, in order.
    fn training(self, segments: &[Labelled]) -> impl Iterator<Item = &SensorSample> + Clone {
        segments.iter().enumerate().flat_map(move |(i, s)| {
            let all = s.samples.as_slice();
            let (before, after) = match self {
                Held::Whole(k) if k == i => (&all[..0], &all[..0]),
                Held::Stretch {
                    segment,
                    start,
                    len,
                } if segment == i => (&all[..start], &all[start + len..]),
                _ => (all, &all[..0]),
            };
            before.iter().chain(after)
        })
    }
}

/// Splits `segments` (every usable segment of every log, in order) holding out about
/// `fraction` of the samples for verification; each part has at least `min` samples
/// ([`crate::import::min_useful_samples`]). See the [module docs](self) for which part.
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
    // Whole segments about the wanted size that leave enough to train on, the closest to it
    // first (the later of equals).
    let mut wholes: Vec<usize> = (0..segments.len())
        .filter(|&i| {
            let n = segments[i].samples.len();
            n >= min && total - n >= min && (n as f64) <= 2.0 * target && (n as f64) >= 0.5 * target
        })
        .collect();
    let distance = |i: usize| (segments[i].samples.len() as f64 - target).abs();
    wholes.sort_by(|&i, &j| distance(i).total_cmp(&distance(j)).then(j.cmp(&i)));
    // Else stretches of the longest segment (the later of equals), the last part first.
    let stretches = || -> Option<Vec<Held>> {
        let k = segments
            .iter()
            .enumerate()
            .rev()
            .max_by_key(|(_, s)| s.samples.len())
            .map(|(i, _)| i)?;
        let n = segments[k].samples.len();
        let len = ((n as f64) * fraction.min(target / n as f64)).round() as usize;
        let len = len.max(min);
        if len >= n || n - len < min {
            return None;
        }
        let last = n - len;
        let mut starts: Vec<usize> = (0..=OFFSETS).rev().map(|j| j * last / OFFSETS).collect();
        starts.dedup();
        Some(
            starts
                .into_iter()
                .map(|start| Held::Stretch {
                    segment: k,
                    start,
                    len,
                })
                .collect(),
        )
    };
    let candidates: Vec<Held> = match wholes.first() {
        Some(_) => wholes.iter().map(|&k| Held::Whole(k)).collect(),
        None => stretches().ok_or(too_short)?,
    };
    // The usual choice, unless it takes a moved stick's excitation (module docs).
    let log_stds = stick_stds(segments.iter().flat_map(|s| &s.samples));
    let score = |h: &Held| kept(&log_stds, h.training(&segments));
    let usual = candidates[0];
    let (usual_kept, stick) = score(&usual);
    let mut chosen = (usual, usual_kept);
    if usual_kept < KEEP_EXCITATION {
        let others = candidates
            .iter()
            .skip(1)
            .copied()
            .chain(if wholes.is_empty() {
                Vec::new()
            } else {
                stretches().unwrap_or_default()
            });
        // The first that keeps enough (the closest to the usual choice: the held-out part
        // stays as late, and as excited, as it can), else the one that keeps the most.
        for h in others {
            let (k, _) = score(&h);
            if k > chosen.1 {
                chosen = (h, k);
                if k >= KEEP_EXCITATION {
                    break;
                }
            }
        }
    }
    let moved = (chosen.0 != usual).then(|| {
        let name = stick.map_or("a stick", |k| STICK_NAMES[k]);
        let instead = match usual {
            Held::Whole(k) => format!("segment {} of {}", segments[k].segment, segments[k].file),
            Held::Stretch { .. } => "the last part".to_string(),
        };
        format!(
            ", not {instead}: that held most of the {name}'s excitation (the training data would have kept {:.0} % of its standard deviation; here every stick the log moves keeps at least {:.0} % of its own)",
            100.0 * usual_kept,
            100.0 * chosen.1
        )
    });
    let moved = moved.unwrap_or_default();
    let mut segments = segments;
    match chosen.0 {
        Held::Whole(k) => {
            let held = segments.remove(k);
            let (a, b) = span(&held.samples);
            let n = held.samples.len();
            Ok(Split {
                how: format!(
                    "held out for verification: segment {} of {} ({a:.2}–{b:.2} s, {n} samples, {:.0} % of the data){moved}; trained on the other {} segment(s)",
                    held.segment,
                    held.file,
                    100.0 * n as f64 / total as f64,
                    segments.len()
                ),
                training: segments.into_iter().map(|s| s.samples).collect(),
                verification: held.samples,
            })
        }
        Held::Stretch {
            segment: k,
            start,
            len,
        } => {
            let whole = std::mem::take(&mut segments[k].samples);
            let n = whole.len();
            let (before, rest) = whole.split_at(start);
            let (held, after) = rest.split_at(len);
            let (a, b) = span(held);
            let which = if start + len == n {
                format!("the last {len} samples")
            } else {
                format!("{len} samples")
            };
            let rest = if start > 0 && start + len < n {
                "the rest (the parts before and after it)"
            } else {
                "the rest"
            };
            let how = format!(
                "held out for verification: {which} of segment {} of {} ({a:.2}–{b:.2} s, {:.0} % of the data){moved}; trained on {rest}",
                segments[k].segment,
                segments[k].file,
                100.0 * len as f64 / total as f64
            );
            let mut parts = [before.to_vec(), after.to_vec()].into_iter();
            let held = held.to_vec();
            // The parts before and after the held-out stretch take its segment's place.
            let training: Vec<Vec<SensorSample>> = segments
                .into_iter()
                .enumerate()
                .flat_map(|(i, s)| {
                    if i == k {
                        parts.by_ref().collect()
                    } else {
                        vec![s.samples]
                    }
                })
                .collect();
            Ok(Split {
                training: training.into_iter().filter(|s| s.len() > 1).collect(),
                verification: held,
                how,
            })
        }
    }
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

    /// `seg` with stick `k` swept (amplitude 0.2) over samples `from..to`.
    fn swept(mut l: Labelled, k: usize, from: usize, to: usize) -> Labelled {
        for (i, s) in l.samples.iter_mut().enumerate().take(to).skip(from) {
            let x = 0.2 * (i as f64 * 0.3).sin();
            match k {
                0 => s.sticks.col = x,
                1 => s.sticks.ped = x,
                2 => s.sticks.lon = x,
                _ => s.sticks.lat = x,
            }
        }
        l
    }

    /// The least kept fraction of a moved stick's standard deviation in `split`'s training.
    fn least_kept(split: &Split) -> f64 {
        let training = || split.training.iter().flatten();
        kept(
            &stick_stds(training().chain(&split.verification)),
            training(),
        )
        .0
    }

    #[test]
    fn a_stick_moved_only_in_the_last_part_stays_in_the_training_data() {
        // Longitudinal cyclic, then lateral, then pedal, then collective, one after another:
        // the last 30 % is most of the collective's sweep.
        let mut l = seg("a.csv", 1, 1000, 0.0);
        for (k, from) in [(2, 0), (3, 250), (1, 500), (0, 750)] {
            l = swept(l, k, from, from + 250);
        }
        let usual = split(vec![l.clone()], 0.3, 100).unwrap();
        assert_eq!(usual.verification.len(), 300);
        assert!(usual.how.contains("not the last part"), "{}", usual.how);
        assert!(usual.how.contains("collective"), "{}", usual.how);
        assert!(
            usual
                .how
                .ends_with("trained on the rest (the parts before and after it)"),
            "{}",
            usual.how
        );
        assert!(least_kept(&usual) >= KEEP_EXCITATION, "{}", usual.how);
        // The parts before and after it, in time order, and nothing lost or doubled.
        assert_eq!(usual.training.len(), 2);
        let held = (usual.verification[0].t, usual.verification[299].t);
        assert!(usual.training[0].last().unwrap().t < held.0);
        assert!(usual.training[1][0].t > held.1);
        assert_eq!(usual.training.iter().map(Vec::len).sum::<usize>(), 700);
    }

    #[test]
    fn sticks_moved_throughout_keep_the_end_held_out() {
        let mut l = seg("a.csv", 1, 1000, 0.0);
        for k in 0..4 {
            l = swept(l, k, 0, 1000);
        }
        let s = split(vec![l], 0.3, 100).unwrap();
        assert!(s.how.contains("the last 300 samples"), "{}", s.how);
        assert!(!s.how.contains("not the"), "{}", s.how);
    }

    #[test]
    fn a_segment_holding_a_sticks_only_excitation_is_not_held_out_whole() {
        // Segment 2 is about the wanted size, but the only one where the collective moves.
        let a = swept(seg("a.ulg", 1, 700, 0.0), 2, 0, 700);
        let b = swept(seg("a.ulg", 2, 300, 20.0), 0, 0, 300);
        let s = split(vec![a, b], 0.3, 100).unwrap();
        assert!(s.how.contains("not segment 2 of a.ulg"), "{}", s.how);
        assert!(s.how.contains("of segment 1 of a.ulg"), "{}", s.how);
        assert!(least_kept(&s) >= KEEP_EXCITATION, "{}", s.how);
        assert!(s.verification.iter().all(|x| x.t < 20.0));
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
