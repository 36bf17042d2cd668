//! The ablations: the flight default with one of its choices undone, each showing what that
//! choice buys (docs/results.md's and docs/robustness.md's evidence). Studies compare them;
//! a user never flies them, so `rotorid identify` does not run them ([`full_catalogue`] is
//! the product's catalogue followed by these).

use rotorid::hover::{
    flight_sets, BodyFrame, HoverIdentifier, HoverSample, LocalRateModel, LocalVelocityModel,
    Premise, RateAxis, RateStructure, VelocityStructure,
};
use rotorid::rule_base::{PremiseSets, RuleBase};
use rotorid::{FlightIdentifier, HoverConfig};
use rotorid_cli::experiments::{
    at, pin_to_zero, select_terms_with, Identifier, SelectedFlight, Variant,
};

/// The product's catalogue ([`rotorid_cli::experiments::variants`]) followed by the
/// ablations, in the order every study's tables and metrics keep.
pub fn full_catalogue() -> Vec<Variant> {
    let mut all = rotorid_cli::experiments::variants();
    all.extend(ablations());
    all
}

/// The product's catalogue followed by `flight selected 2 SE`, `1 SE` and `0.5 SE`: the term
/// selection asking a removal to beat the check blocks' noise by that many standard errors,
/// or to leave fewer free-run windows diverging ([`select_terms_with`]); `rotorid-lab
/// identify-terms`, docs/term-evidence.md. Its `flight selected` keeps every model on the
/// flight default's speed, as the three others do: the study compares the term selections
/// alone.
pub fn term_evidence_catalogue() -> Vec<Variant> {
    let mut all = rotorid_cli::experiments::variants_with(false);
    all.extend([
        Variant {
            name: "flight selected 2 SE",
            description: "flight selected where a term is switched off only if its removal lowers the free run on the check blocks by more than two standard errors of the paired block differences, or leaves fewer free-run windows diverging",
            kind: None,
            build: |training, period| selected_asking(2.0, training, period),
        },
        Variant {
            name: "flight selected 1 SE",
            description: "flight selected where a term is switched off only if its removal lowers the free run on the check blocks by more than one standard error of the paired block differences, or leaves fewer free-run windows diverging",
            kind: None,
            build: |training, period| selected_asking(1.0, training, period),
        },
        Variant {
            name: "flight selected 0.5 SE",
            description: "flight selected where a term is switched off only if its removal lowers the free run on the check blocks by more than half a standard error of the paired block differences, or leaves fewer free-run windows diverging",
            kind: None,
            build: |training, period| selected_asking(0.5, training, period),
        },
    ]);
    all
}

/// The flight default with the terms whose removal beats the check blocks' noise by `k`
/// standard errors switched off.
fn selected_asking(
    k: f64,
    training: &[Vec<HoverSample<f32>>],
    period: u32,
) -> Result<Box<dyn Identifier>, rotorid::Error> {
    let selection = select_terms_with(training, period, Some(k))?;
    Ok(Box::new(SelectedFlight::new(selection.mask, period)?))
}

/// The ablations of the flight default.
pub fn ablations() -> Vec<Variant> {
    vec![
        Variant {
            name: "flight extended velocity",
            description: "the flight default with the extended structure's translational model (VelocityStructure::Extended: drag in inertial axes on the sample's own velocity, thrust proportional to the collective): what the flight structure's translational terms add",
            kind: None,
            build: |_, period| Ok(Box::new(flight_with_extended_velocity(period)?)),
        },
        Variant {
            name: "flight first-order rates",
            description: "the flight default with the rate models' second-order term held at zero (each rule's η pinned by a zero prior variance): what that term buys in free run and costs at one step",
            kind: None,
            build: |_, period| Ok(Box::new(flight_with_first_order_rates(period)?)),
        },
        Variant {
            name: "flight proportional thrust",
            description: "the flight default with the translational model's thrust at zero collective held at zero (each rule's α0 pinned by a zero prior variance): the thrust proportional to the collective, as in Eq. 27; what the affine thrust buys",
            kind: None,
            build: |_, period| Ok(Box::new(flight_with_proportional_thrust(period)?)),
        },
        Variant {
            name: "flight yaw on side speed",
            description: "the flight default with its yaw model scheduled on forward and side speed (3 x 3 rules; side sets at -5, 0, 5 m/s, σ 2.5): whether the yaw trim in sideways flight is a matter of scheduling",
            kind: None,
            build: |_, period| Ok(Box::new(flight_with_side_speed_yaw(period)?)),
        },
        Variant {
            name: "flight data sets",
            description: "the flight default with its forward-speed sets placed at the training data's quantiles (noise floor 3σ_n)",
            kind: None,
            build: |training, period| {
                Ok(Box::new(FlightIdentifier::<f32>::flight(
                    at(HoverConfig::default(), period),
                    forward_speed_sets(training)?,
                )?))
            },
        },
    ]
}

/// [`FlightIdentifier`] with the extended structure's translational model (7 terms; see
/// [`flight_with_extended_velocity`]).
type ExtendedVelocityIdentifier = HoverIdentifier<
    f32,
    LocalVelocityModel<f32, 3, 7, 28>,
    LocalRateModel<f32, 3, 7, 28>,
    LocalRateModel<f32, 3, 7, 28>,
    LocalRateModel<f32, 3, 7, 28>,
>;

/// [`FlightIdentifier`] whose translational model has the extended structure
/// (`VelocityStructure::Extended`: drag per inertial axis, thrust proportional to the
/// collective) instead of the flight structure (drag along and across the heading, thrust
/// affine in the collective); the same premise, sets, rate models and settings.
fn flight_with_extended_velocity(
    period: u32,
) -> Result<ExtendedVelocityIdentifier, rotorid::Error> {
    let config = at(HoverConfig::default(), period);
    let flight = FlightIdentifier::<f32>::flight(config, flight_sets())?;
    let structure = VelocityStructure::Extended;
    let velocity = LocalVelocityModel::<f32, 3, 7, 28>::with_scaling(
        flight.velocity_model().ts().rules().clone(),
        structure,
        Premise::HeadingVelocity,
        config.rls,
        structure.helicopter_scaling(),
    )?;
    HoverIdentifier::new(
        velocity,
        flight.pitch_model().clone(),
        flight.yaw_model().clone(),
        flight.roll_model().clone(),
        config,
    )
}

/// [`FlightIdentifier`] whose rate models learn without their second-order term `η Δω(k)`
/// (index 6 of [`RateStructure::Flight`]'s terms; see [`pin_to_zero`]). Everything else is the
/// flight default's.
fn flight_with_first_order_rates(period: u32) -> Result<FlightIdentifier<f32>, rotorid::Error> {
    const SECOND_ORDER: usize = 6;
    let mut flight =
        FlightIdentifier::<f32>::flight(at(HoverConfig::default(), period), flight_sets())?;
    let mut snapshot = flight.export();
    for model in [&mut snapshot.pitch, &mut snapshot.yaw, &mut snapshot.roll] {
        pin_to_zero(model, SECOND_ORDER);
    }
    flight.import(&snapshot)?;
    Ok(flight)
}

/// [`FlightIdentifier`] whose translational model learns without the thrust at zero
/// collective `α0` (index 7 of [`VelocityStructure::Flight`]'s terms; see [`pin_to_zero`]): the
/// thrust proportional to the collective, as in Eq. 27. Everything else is the flight
/// default's.
fn flight_with_proportional_thrust(period: u32) -> Result<FlightIdentifier<f32>, rotorid::Error> {
    const AFFINE_THRUST: usize = 7;
    let mut flight =
        FlightIdentifier::<f32>::flight(at(HoverConfig::default(), period), flight_sets())?;
    let mut snapshot = flight.export();
    pin_to_zero(&mut snapshot.velocity, AFFINE_THRUST);
    flight.import(&snapshot)?;
    Ok(flight)
}

/// [`FlightIdentifier`] with a 9-rule yaw model (see [`flight_with_side_speed_yaw`]).
type SideSpeedYawIdentifier = HoverIdentifier<
    f32,
    LocalVelocityModel<f32, 3, 8, 36>,
    LocalRateModel<f32, 3, 7, 28>,
    LocalRateModel<f32, 9, 7, 28>,
    LocalRateModel<f32, 3, 7, 28>,
>;

/// [`FlightIdentifier`] whose yaw model is scheduled on the side speed too: the forward-speed
/// sets times three side-speed sets (left shoulder at −5 m/s, Gaussian at 0, right shoulder at
/// 5 m/s, σ = 2.5 m/s: the forward sets' spacing and spread), 9 rules learnt locally; the
/// other models, the terms and the settings are the flight default's.
fn flight_with_side_speed_yaw(period: u32) -> Result<SideSpeedYawIdentifier, rotorid::Error> {
    let config = at(HoverConfig::default(), period);
    let flight = FlightIdentifier::<f32>::flight(config, flight_sets())?;
    let side = rotorid::hover::table3::three_sets((-5.0, 2.5), (0.0, 2.5), (5.0, 2.5));
    let rules = RuleBase::new([flight_sets(), side, PremiseSets::new()])?;
    let structure = RateStructure::Flight;
    let yaw = LocalRateModel::<f32, 9, 7, 28>::with_scaling(
        RateAxis::Yaw,
        rules,
        structure,
        Premise::HeadingVelocity,
        config.rls,
        structure.helicopter_scaling(RateAxis::Yaw),
    )?;
    HoverIdentifier::new(
        flight.velocity_model().clone(),
        flight.pitch_model().clone(),
        yaw,
        flight.roll_model().clone(),
        config,
    )
}

/// The forward-speed sets of the flight identifier placed from training logs
/// ([`rotorid::premise::quantile_sets`], three sets; noise from the first log's first
/// differences). The core's [`flight_sets`] when there are too few samples.
pub fn forward_speed_sets(
    training: &[Vec<HoverSample<f32>>],
) -> Result<rotorid::rule_base::PremiseSets<f32>, rotorid::Error> {
    let forward = |s: &HoverSample<f32>| {
        let frame = BodyFrame::of(&s.attitude);
        Premise::HeadingVelocity.of(s, &frame)[0]
    };
    let mut values: Vec<f32> = training.iter().flatten().map(forward).collect();
    let first: Vec<f32> = training
        .first()
        .map_or_else(Vec::new, |l| l.iter().map(forward).collect());
    let mut scratch = vec![0.0f32; first.len()];
    match rotorid::premise::noise_std(&first, &mut scratch) {
        Some(noise) if !values.is_empty() => rotorid::premise::quantile_sets(&mut values, 3, noise),
        _ => Ok(flight_sets()),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn first_order_rates_hold_eta_at_zero_and_learn_the_rest() {
        let log = rotorid_sim::flights::identification_flight_for(1, 20.0).unwrap();
        let samples = rotorid_sim::flights::to_hover_samples(&log);
        let mut pinned = flight_with_first_order_rates(20_000).unwrap();
        let mut flight =
            FlightIdentifier::<f32>::flight(HoverConfig::default(), flight_sets()).unwrap();
        for s in &samples {
            pinned.step(s).unwrap();
            flight.step(s).unwrap();
        }
        let (p, f) = (pinned.export(), flight.export());
        let diagonal = 6 * 7 / 2 + 6;
        for (pm, fm) in [(&p.pitch, &f.pitch), (&p.yaw, &f.yaw), (&p.roll, &f.roll)] {
            // The hover rule fires on this flight: it learns.
            let (hover, flight_hover) = (&pm[0], &fm[0]);
            assert_eq!(hover.theta[6].to_bits(), 0.0f32.to_bits());
            assert_eq!(hover.factor[diagonal].to_bits(), 0.0f32.to_bits());
            assert!(hover.updates > 0);
            assert!(
                hover.theta[..6].iter().all(|&t| t != 0.0),
                "{:?}",
                hover.theta
            );
            assert_ne!(flight_hover.theta[6], 0.0);
            for rule in pm {
                assert_eq!(rule.theta[6].to_bits(), 0.0f32.to_bits());
            }
        }
        // The velocity model is the flight default's, bit for bit.
        assert_eq!(p.velocity, f.velocity);
    }
}
