//! `rotorid simulate` as a library call: fly the simulator ([`rotorid_sim`]) and return the
//! sensor samples of the flight log (the command writes them as CSV; the Python package turns
//! them into a DataFrame).

use rotorid_sim::envelope::{self, EnvelopeKind};
use rotorid_sim::flights;
use rotorid_sim::plant::{Airframe, FlightConfig, NoiseStd, PlantError, SensorSample, StickScale};

/// Which flight to fly.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum FlightKind {
    /// The four Table 2 sweeps (lon, lat, ped, col), 255 s in full.
    Identification,
    /// Doublets and 3-2-1-1 multisteps on all controls between hover periods.
    Verification,
    /// Wide envelope: 12 operating points, doublets and multisteps throughout (300 s).
    Envelope,
    /// The held-out envelope flight: 8 other operating points (200 s).
    EnvelopeVerification,
}

/// The arguments of a simulated flight (those of `rotorid simulate`).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SimulateArgs {
    /// Flight kind.
    pub kind: FlightKind,
    /// Seed of noise, turbulence, jitter and (verification) manoeuvres.
    pub seed: u64,
    /// Duration (s); `None`: the kind's default. Not for envelope flights.
    pub duration: Option<f64>,
    /// No measurement noise and no turbulence.
    pub clean: bool,
    /// Measurement noise as a multiple of the default (0 to 100).
    pub noise_scale: f64,
    /// The simulated helicopter.
    pub airframe: Airframe,
    /// Seed of a variation of the airframe (`Helicopter::varied`).
    pub variation: Option<u64>,
    /// Cyclic control power as a fraction of the airframe's (0.1 to 2; 1 unchanged): both
    /// cyclic-to-flapping gains `A_lon`, `B_lat` are multiplied by it, and the pilot's stick
    /// scaling is left as for the undamaged airframe (a worn or damaged rotor the pilot has
    /// not retuned for).
    pub cyclic_power: f64,
    /// Fly the airframe's linearisation about hover (`rotorid_sim::plant::LinearHover`): a
    /// linear helicopter model with the plant's trim and derivatives there.
    pub linear: bool,
    /// Sample instants exactly every period (no jitter).
    pub no_jitter: bool,
}

impl SimulateArgs {
    /// A realistic (noisy, turbulent) flight of `kind` on the X-Cell 60.
    pub fn new(kind: FlightKind, seed: u64) -> Self {
        Self {
            kind,
            seed,
            duration: None,
            clean: false,
            noise_scale: 1.0,
            airframe: Airframe::XCell60,
            variation: None,
            cyclic_power: 1.0,
            linear: false,
            no_jitter: false,
        }
    }
}

/// What went wrong in a simulation.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum SimulateError {
    /// The duration is out of range.
    #[error("--duration must be in (0, 36000] s, got {0}")]
    Duration(f64),
    /// The noise scale is out of range.
    #[error("--noise-scale must be in [0, 100], got {0}")]
    NoiseScale(f64),
    /// The cyclic control power factor is out of range.
    #[error("--cyclic-power must be in [0.1, 2], got {0}")]
    CyclicPower(f64),
    /// The pilot's gain scale is out of range.
    #[error("--pilot-gain-scale must be in [0.05, 10], got {0}")]
    PilotGainScale(f64),
    /// An identification flight longer than its sweeps.
    #[error(
        "--duration {given} s: the identification flight (the four Table 2 sweeps) lasts {full} s; \
         give at most that, or fly a verification flight for longer"
    )]
    LongerThanSweeps {
        /// The duration asked for (s).
        given: f64,
        /// The sweeps' length (s).
        full: f64,
    },
    /// A duration for an envelope flight.
    #[error("--duration does not apply to envelope flights (their length is their schedule's)")]
    EnvelopeDuration,
    /// The airframe cannot be flown.
    #[error("plant {airframe}")]
    Airframe {
        /// Its name.
        airframe: &'static str,
        /// Why.
        source: PlantError,
    },
    /// The airframe's variation cannot hover.
    #[error("plant {airframe}, variation {seed}: this variation cannot hover (try another seed)")]
    Variation {
        /// The airframe's name.
        airframe: &'static str,
        /// The variation's seed.
        seed: u64,
        /// Why.
        source: PlantError,
    },
    /// The flight diverged or was misconfigured.
    #[error("simulation")]
    Simulation(#[source] PlantError),
}

/// Flies the simulator as `args` say; the flight log's samples.
///
/// # Errors
/// [`SimulateError`]: an argument out of range, or a flight the plant cannot fly.
pub fn simulate(args: &SimulateArgs) -> Result<Vec<SensorSample>, SimulateError> {
    simulate_with_pilot_gain(args, 1.0)
}

/// [`simulate`] with the pilot's feedback `pilot_gain_scale` times as strong as its hover-hold
/// gains (0.05 to 10; exactly 1 is [`simulate`], bit for bit): every stick output of the
/// hover-hold pilot, and so of the slow pilot on a swept channel, times the factor. Used to
/// quantify the closed-loop bias of the identification (docs/closed-loop.md); a feedback too
/// weak or too strong to hold the helicopter diverges, and the error says so.
///
/// A separate call rather than a field of [`SimulateArgs`], so that callers building the
/// arguments field by field keep compiling.
///
/// # Errors
/// As [`simulate`], and [`SimulateError::PilotGainScale`] out of range.
pub fn simulate_with_pilot_gain(
    args: &SimulateArgs,
    pilot_gain_scale: f64,
) -> Result<Vec<SensorSample>, SimulateError> {
    let scale = args.noise_scale;
    if !(scale.is_finite() && (0.0..=100.0).contains(&scale)) {
        return Err(SimulateError::NoiseScale(scale));
    }
    let power = args.cyclic_power;
    if !(power.is_finite() && (0.1..=2.0).contains(&power)) {
        return Err(SimulateError::CyclicPower(power));
    }
    let feedback = pilot_gain_scale;
    if !(feedback.is_finite() && (0.05..=10.0).contains(&feedback)) {
        return Err(SimulateError::PilotGainScale(feedback));
    }
    if let Some(d) = args.duration {
        if !(d.is_finite() && d > 0.0 && d <= 36_000.0) {
            return Err(SimulateError::Duration(d));
        }
    }
    if let (FlightKind::Identification, Some(d)) = (args.kind, args.duration) {
        let full = flights::identification_duration_s();
        if d > full {
            return Err(SimulateError::LongerThanSweeps { given: d, full });
        }
    }
    let seed = args.seed;
    let airframe = args.airframe;
    let sensors = if args.clean {
        FlightConfig::default()
    } else {
        let realistic = FlightConfig::realistic(seed, 0.0);
        FlightConfig {
            noise: realistic.noise.map(|n| NoiseStd {
                velocity: n.velocity * scale,
                rate: n.rate * scale,
                angle: n.angle * scale,
            }),
            ..realistic
        }
    };
    let config = FlightConfig { seed, ..sensors }
        .for_airframe(airframe)
        .map_err(|source| SimulateError::Airframe {
            airframe: airframe.name(),
            source,
        })?;
    let mut config = match args.variation {
        Some(seed) => config
            .varied(seed)
            .map_err(|source| SimulateError::Variation {
                airframe: airframe.name(),
                seed,
                source,
            })?,
        None => config,
    };
    config.linear = args.linear;
    if args.no_jitter {
        config.jitter = 0.0;
    }
    // Only when asked: a factor of exactly 1 leaves every number of the flight as it was.
    if power != 1.0 {
        config.params.a_lon *= power;
        config.params.b_lat *= power;
    }
    // The same for the pilot: every loop's stick output times the factor (the attitude
    // reference per speed is an angle and stays), so each loop gain scales by it.
    if feedback != 1.0 {
        config.gains = config.gains.scaled(&StickScale {
            col: feedback,
            ped: feedback,
            lon: feedback,
            lat: feedback,
        });
    }
    match args.kind {
        FlightKind::Identification => {
            flights::identification_flight_with(&config, args.duration.unwrap_or(f64::INFINITY))
        }
        FlightKind::Verification => flights::verification_flight_with(&FlightConfig {
            duration: args.duration.unwrap_or(120.0),
            ..config
        }),
        FlightKind::Envelope | FlightKind::EnvelopeVerification => {
            let kind = match args.kind {
                FlightKind::Envelope => EnvelopeKind::Identification,
                _ => EnvelopeKind::Verification,
            };
            if args.duration.is_some() {
                return Err(SimulateError::EnvelopeDuration);
            }
            envelope::envelope_flight_with(&config, kind)
        }
    }
    .map_err(SimulateError::Simulation)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn flight(power: f64) -> Result<Vec<SensorSample>, SimulateError> {
        simulate(&SimulateArgs {
            duration: Some(8.0),
            cyclic_power: power,
            ..SimulateArgs::new(FlightKind::Verification, 3)
        })
    }

    /// The linearisation starts from the plant's trim (the first sample is the same) and then
    /// flies differently; without jitter every sample is 20 ms after the last.
    #[test]
    fn the_linear_plant_starts_at_the_same_trim_and_no_jitter_is_exact() {
        let args = |linear, no_jitter| SimulateArgs {
            duration: Some(8.0),
            clean: true,
            linear,
            no_jitter,
            ..SimulateArgs::new(FlightKind::Verification, 3)
        };
        let plant = simulate(&args(false, false)).unwrap();
        let linear = simulate(&args(true, false)).unwrap();
        assert_eq!(linear.len(), plant.len());
        assert_eq!(linear[0], plant[0]);
        assert_ne!(linear, plant);
        let exact = simulate(&args(true, true)).unwrap();
        assert!(exact
            .windows(2)
            .all(|w| (w[1].t - w[0].t - 0.02).abs() < 1e-9));
        assert!(linear
            .windows(2)
            .any(|w| (w[1].t - w[0].t - 0.02).abs() > 1e-4));
    }

    #[test]
    fn cyclic_power_one_is_the_undamaged_flight_and_others_differ() {
        let base = flight(1.0).unwrap();
        let plain = simulate(&SimulateArgs {
            duration: Some(8.0),
            ..SimulateArgs::new(FlightKind::Verification, 3)
        })
        .unwrap();
        assert_eq!(base, plain);
        let weak = flight(0.5).unwrap();
        assert_eq!(weak.len(), base.len());
        assert_ne!(weak, base);
    }

    #[test]
    fn cyclic_power_out_of_range_is_refused() {
        for bad in [0.0, 0.09, 2.5, f64::NAN, f64::INFINITY] {
            assert!(
                matches!(flight(bad), Err(SimulateError::CyclicPower(_))),
                "{bad}"
            );
        }
    }
}
