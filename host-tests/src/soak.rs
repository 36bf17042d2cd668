//! The soak: the f32 flight identifier with forgetting, learning without pause over a day of
//! simulated flight (4.32 M steps at 50 Hz), an hour of it without excitation.
//!
//! Flights follow one another (envelope flights and Table 2 sweeps with new seeds; each new
//! flight starts a new sample chain with `resume`); the quiet hour is pilot-held hover with
//! sensor noise and turbulence but no manoeuvre, where forgetting would wind the covariance up
//! without the guard. Every step is checked (finite prediction); every [`CHECK_EVERY`] steps
//! the covariance of every rule (trace, smallest and largest diagonal entry) and the largest
//! parameter are recorded; after the quiet hour the time for the rate error to come back to its
//! level before the quiet hour is measured.

use rotorid::hover::{flight_sets, HoverSample};
use rotorid::rls::RlsConfig;
use rotorid::{FlightIdentifier, HoverConfig};

use rotorid_sim::envelope::{envelope_flight, EnvelopeKind};
use rotorid_sim::flights::{identification_flight, to_hover_samples};
use rotorid_sim::plant::{simulate, Excitation, FlightConfig, PlantError};

/// Forgetting factor of the soak: a memory of about 2 000 samples (40 s).
pub const FORGETTING: f64 = 0.9995;
/// Trace bound of the windup guard, per rule (scaled coordinates; P(0) has trace 7 · 10⁶).
pub const MAX_TRACE: f64 = 1e7;
/// Steps between covariance checks.
pub const CHECK_EVERY: u64 = 10_000;
/// Window of the rolling rate error (samples, 10 s).
pub const ERROR_WINDOW: usize = 500;

/// The soak's schedule.
#[derive(Debug, Clone, Copy)]
pub struct SoakPlan {
    /// Total steps.
    pub steps: u64,
    /// Step at which the quiet (unexcited) period starts.
    pub quiet_start: u64,
    /// Steps of the quiet period.
    pub quiet_steps: u64,
}

impl SoakPlan {
    /// 24 h at 50 Hz with the quiet hour from hour 12.
    pub fn day() -> Self {
        Self {
            steps: 4_320_000,
            quiet_start: 2_160_000,
            quiet_steps: 180_000,
        }
    }
}

/// What the soak measured.
#[derive(Debug, Clone, Default)]
pub struct SoakReport {
    /// Steps made (learning steps and chain starts).
    pub steps: u64,
    /// Flights flown.
    pub flights: u64,
    /// Steps whose sample the identifier refused (none expected from the simulator).
    pub rejected: u64,
    /// Steps whose prediction was not finite (must be 0).
    pub non_finite: u64,
    /// Largest trace(P) of any rule at any check (scaled coordinates).
    pub max_trace: f64,
    /// Smallest diagonal entry of P of any rule at any check (must stay > 0).
    pub min_diagonal: f64,
    /// Largest diagonal entry of P of any rule at any check.
    pub max_diagonal: f64,
    /// Largest |θ| of any rule at any check (scaled coordinates).
    pub max_parameter: f64,
    /// Windup-guard activations summed over every rule's estimator at the end.
    pub windup_guards: u64,
    /// Mean absolute one-step error of q, r, p (deg/s) over the last excited hour before the
    /// quiet period.
    pub error_before_quiet: f64,
    /// The same over the quiet period.
    pub error_quiet: f64,
    /// Seconds after excitation returned until the rolling 10 s rate error was back within
    /// 1.2 × `error_before_quiet` (`None`: never within the run).
    pub recovery_s: Option<f64>,
}

/// Covariance and parameter extremes over every rule of the four models.
fn extremes(id: &FlightIdentifier<f32>, r: &mut SoakReport) {
    let mut visit = |rule: rotorid::rls::RlsView<'_, f32>| {
        r.max_trace = r.max_trace.max(f64::from(rule.trace()));
        for x in rule.covariance_diagonal() {
            r.min_diagonal = r.min_diagonal.min(f64::from(x));
            r.max_diagonal = r.max_diagonal.max(f64::from(x));
        }
        for &t in rule.parameters() {
            r.max_parameter = r.max_parameter.max(f64::from(t.abs()));
        }
    };
    for i in 0..3 {
        if let Some(rule) = id.velocity_model().ts().rule(i) {
            visit(rule);
        }
        for m in [id.pitch_model(), id.yaw_model(), id.roll_model()] {
            if let Some(rule) = m.ts().rule(i) {
                visit(rule);
            }
        }
    }
}

fn windup_guards(id: &FlightIdentifier<f32>) -> u64 {
    let mut n = 0u64;
    for i in 0..3 {
        let v = id.velocity_model().ts().rule(i);
        let rates = [id.pitch_model(), id.yaw_model(), id.roll_model()].map(|m| m.ts().rule(i));
        for rule in std::iter::once(v).chain(rates).flatten() {
            n += u64::from(rule.counters().windup_guards);
        }
    }
    n
}

/// Flight `k` of the excited part: envelope flights and sweeps in turn, new seeds.
fn excited_flight(k: u64) -> Result<Vec<HoverSample<f32>>, PlantError> {
    let seed = 1000 + k;
    let log = match k % 3 {
        0 => envelope_flight(seed, EnvelopeKind::Identification)?,
        1 => envelope_flight(seed, EnvelopeKind::Verification)?,
        _ => identification_flight(seed)?,
    };
    Ok(to_hover_samples(&log))
}

/// Pilot-held hover, noise and turbulence, no manoeuvre.
fn quiet_flight(seed: u64, seconds: f64) -> Result<Vec<HoverSample<f32>>, PlantError> {
    let config = FlightConfig::realistic(seed, seconds);
    Ok(to_hover_samples(&simulate(&config, &mut |_, _| {
        Excitation::none()
    })?))
}

/// Why a soak could not run.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[non_exhaustive]
pub enum SoakError {
    /// The flight identifier could not be built.
    #[error("cannot build the flight identifier")]
    Identifier(#[source] rotorid::Error),
    /// A flight of the soak could not be simulated.
    #[error("flight {flight}: simulation")]
    Flight {
        /// The flight's number in the soak (from 0).
        flight: u64,
        /// The plant's reason.
        #[source]
        source: PlantError,
    },
}

/// Runs the soak; `progress` gets the steps made so far after each flight.
pub fn run(plan: SoakPlan, progress: &mut dyn FnMut(u64)) -> Result<SoakReport, SoakError> {
    let config = HoverConfig {
        rls: RlsConfig::default().with_forgetting(FORGETTING as f32, MAX_TRACE as f32),
        ..HoverConfig::default()
    };
    let mut id =
        FlightIdentifier::<f32>::flight(config, flight_sets()).map_err(SoakError::Identifier)?;
    let mut r = SoakReport {
        min_diagonal: f64::INFINITY,
        ..SoakReport::default()
    };
    let hour = 180_000u64;
    let quiet_end = plan.quiet_start + plan.quiet_steps;
    let (mut before_sum, mut before_n, mut quiet_sum, mut quiet_n) = (0.0, 0u64, 0.0, 0u64);
    let mut window: std::collections::VecDeque<f64> = std::collections::VecDeque::new();
    let mut window_sum = 0.0;
    let mut k_flight = 0u64;
    while r.steps < plan.steps {
        let quiet = r.steps >= plan.quiet_start && r.steps < quiet_end;
        let samples = if quiet {
            let seconds = (quiet_end - r.steps) as f64 / 50.0;
            quiet_flight(5_000 + k_flight, seconds)
        } else {
            excited_flight(k_flight)
        }
        .map_err(|source| SoakError::Flight {
            flight: k_flight,
            source,
        })?;
        k_flight += 1;
        r.flights += 1;
        let mut pending: Option<rotorid::HoverState<f32>> = None;
        let mut first = true;
        for s in &samples {
            if r.steps >= plan.steps
                || (!quiet && r.steps == plan.quiet_start && plan.quiet_steps > 0)
            {
                break;
            }
            let out = if first {
                first = false;
                id.resume(s).map(|p| (p, None))
            } else {
                id.step(s).map(|o| (o.prediction, o.innovation))
            };
            r.steps += 1;
            match out {
                Ok((prediction, _)) => {
                    if !prediction.to_array().iter().all(|x| x.is_finite()) {
                        r.non_finite += 1;
                    }
                    if let Some(p) = pending {
                        let e = (0..3)
                            .map(|i| f64::from((p.rates[i] - s.rates[i]).abs()))
                            .sum::<f64>()
                            / 3.0;
                        let t = r.steps;
                        if t < plan.quiet_start && t + hour >= plan.quiet_start {
                            before_sum += e;
                            before_n += 1;
                        }
                        if t >= plan.quiet_start && t < quiet_end {
                            quiet_sum += e;
                            quiet_n += 1;
                        }
                        window.push_back(e);
                        window_sum += e;
                        if window.len() > ERROR_WINDOW {
                            window_sum -= window.pop_front().unwrap_or(0.0);
                        }
                        if t >= quiet_end && r.recovery_s.is_none() && window.len() == ERROR_WINDOW
                        {
                            let level = before_sum / before_n.max(1) as f64;
                            let since_quiet = t - quiet_end;
                            if since_quiet >= ERROR_WINDOW as u64
                                && window_sum / ERROR_WINDOW as f64 <= 1.2 * level
                            {
                                r.recovery_s = Some(since_quiet as f64 / 50.0);
                            }
                        }
                    }
                    pending = Some(prediction);
                }
                Err(_) => {
                    r.rejected += 1;
                    pending = None;
                }
            }
            if r.steps.is_multiple_of(CHECK_EVERY) {
                extremes(&id, &mut r);
            }
        }
        progress(r.steps);
    }
    extremes(&id, &mut r);
    r.windup_guards = windup_guards(&id);
    r.error_before_quiet = before_sum / before_n.max(1) as f64;
    r.error_quiet = quiet_sum / quiet_n.max(1) as f64;
    Ok(r)
}
