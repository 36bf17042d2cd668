//! Unit tests of the models' shared parts.

use super::{Premise, SharedStrengths};
use crate::hover::table3::three_sets;
use crate::hover::{flight_sets, Attitude, BodyFrame, Controls, HoverSample};
use crate::membership::MembershipFunction::LeftShoulder;
use crate::rule_base::{PremiseSets, RuleBase};

#[test]
fn shared_strengths_are_taken_only_by_the_same_premise_and_sets() {
    let none = PremiseSets::<f32>::new;
    let forward = RuleBase::<f32, 3, 3>::new([flight_sets(), none(), none()]).unwrap();
    let xi = forward.firing_strengths(&[4.0, 1.0, 0.0]).unwrap();
    let shared = SharedStrengths::new(Premise::HeadingVelocity, &forward, &xi);
    let twin = RuleBase::<f32, 3, 3>::new([flight_sets(), none(), none()]).unwrap();
    assert_eq!(shared.for_rules(Premise::HeadingVelocity, &twin), Some(&xi));
    // Another premise, other sets, the same sets on another variable, another rule count.
    assert_eq!(shared.for_rules(Premise::Velocity, &twin), None);
    let moved = three_sets((0.0, 2.5), (5.5, 2.5), (10.0, 2.5));
    let moved = RuleBase::<f32, 3, 3>::new([moved, none(), none()]).unwrap();
    assert_eq!(shared.for_rules(Premise::HeadingVelocity, &moved), None);
    let side = RuleBase::<f32, 3, 3>::new([none(), flight_sets(), none()]).unwrap();
    assert_eq!(shared.for_rules(Premise::HeadingVelocity, &side), None);
    let one = RuleBase::<f32, 3, 1>::single_rule().unwrap();
    assert_eq!(shared.for_rules(Premise::HeadingVelocity, &one), None);
    // Sets are compared bit for bit: a centre of −0 is another set (which would give the
    // same strengths, but sharing does not rely on that).
    let minus = three_sets((-0.0, 2.5), (5.0, 2.5), (10.0, 2.5));
    let minus = RuleBase::<f32, 3, 3>::new([minus, none(), none()]).unwrap();
    assert_eq!(shared.for_rules(Premise::HeadingVelocity, &minus), None);
    // A shoulder where the twin has a Gaussian, same centre and spread.
    let mut kinds = flight_sets::<f32>();
    kinds[1] = LeftShoulder {
        centre: 5.0,
        spread: 2.5,
    };
    let kinds = RuleBase::<f32, 3, 3>::new([kinds, none(), none()]).unwrap();
    assert_eq!(shared.for_rules(Premise::HeadingVelocity, &kinds), None);
}

#[test]
fn horizontal_speed_is_the_same_in_every_direction_and_heading() {
    // 5 m/s flown north, east, south-west and sideways (heading 90° off the track), climbing
    // at 1 m/s (paper axes: x east, y up, z south): one speed, the vertical velocity second.
    let at = |velocity: [f32; 3], yaw: f32| {
        let s = HoverSample {
            time_us: 0,
            attitude: Attitude {
                roll: 0.0,
                pitch: 0.0,
                yaw,
            },
            velocity,
            rates: [0.0; 3],
            controls: Controls::default(),
        };
        Premise::HorizontalSpeed.of(&s, &BodyFrame::of(&s.attitude))
    };
    let d = 5.0 / 2f32.sqrt();
    for (velocity, yaw) in [
        ([0.0, 1.0, -5.0], 0.0),
        ([5.0, 1.0, 0.0], 1.0),
        ([-d, 1.0, d], -2.0),
        ([0.0, 1.0, -5.0], core::f32::consts::FRAC_PI_2),
    ] {
        let p = at(velocity, yaw);
        assert!((p[0] - 5.0).abs() < 1e-6, "{velocity:?}: {p:?}");
        assert_eq!((p[1], p[2]), (1.0, 0.0));
    }
    // The forward speed of the last: zero (all of it is sideways).
    let s = HoverSample {
        time_us: 0,
        attitude: Attitude {
            roll: 0.0,
            pitch: 0.0,
            yaw: core::f32::consts::FRAC_PI_2,
        },
        velocity: [0.0, 1.0, -5.0],
        rates: [0.0; 3],
        controls: Controls::default(),
    };
    let forward = Premise::HeadingVelocity.of(&s, &BodyFrame::of(&s.attitude))[0];
    assert!(forward.abs() < 1e-6, "{forward}");
}
