//! The six equations of the body-axis model: their left sides, regressors and symbols (the
//! table of the [module docs](super)).

/// A regressor column.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(super) enum Term {
    State(usize),
    Stick(usize),
}

/// State indices in [`Point::x`].
pub(super) const U: usize = 0;
pub(super) const V: usize = 1;
pub(super) const W: usize = 2;
pub(super) const P: usize = 3;
pub(super) const Q: usize = 4;
pub(super) const R: usize = 5;
/// Stick indices in [`Point::sticks`], order `col, ped, lon, lat`.
pub(super) const COL: usize = 0;
pub(super) const PED: usize = 1;
pub(super) const LON: usize = 2;
pub(super) const LAT: usize = 3;
pub(super) const STICK_NAMES: [&str; 4] = ["col", "ped", "lon", "lat"];

pub(super) struct Equation {
    pub(super) axis: &'static str,
    pub(super) equation: &'static str,
    /// Unit of the left side.
    pub(super) lhs_unit: &'static str,
    pub(super) terms: &'static [(Term, &'static str, &'static str)],
    pub(super) intercept: &'static str,
}

pub(super) const PER_STICK_ACC: &str = "m/s² per unit stick";
pub(super) const PER_STICK_ANG: &str = "rad/s² per unit stick";
pub(super) const PER_SPEED_ANG: &str = "rad/s² per m/s";

pub(super) const EQUATIONS: [Equation; 6] = [
    Equation {
        axis: "u",
        equation: "u̇ − (r v − q w) + g sinθ = X_u u + X_lon δlon + X_0",
        lhs_unit: "m/s²",
        terms: &[
            (Term::State(U), "X_u", "1/s"),
            (Term::State(Q), "X_q", "m/s² per rad/s"),
            (Term::Stick(LON), "X_lon", PER_STICK_ACC),
        ],
        intercept: "X_0",
    },
    Equation {
        axis: "v",
        equation: "v̇ − (p w − r u) − g cosθ sinφ = Y_v v + Y_lat δlat + Y_ped δped + Y_0",
        lhs_unit: "m/s²",
        terms: &[
            (Term::State(V), "Y_v", "1/s"),
            (Term::State(P), "Y_p", "m/s² per rad/s"),
            (Term::Stick(LAT), "Y_lat", PER_STICK_ACC),
            (Term::Stick(PED), "Y_ped", PER_STICK_ACC),
        ],
        intercept: "Y_0",
    },
    Equation {
        axis: "w",
        equation: "ẇ − (q u − p v) − g cosθ cosφ = Z_w w + Z_col δcol + Z_0",
        lhs_unit: "m/s²",
        terms: &[
            (Term::State(W), "Z_w", "1/s"),
            (Term::Stick(COL), "Z_col", PER_STICK_ACC),
        ],
        intercept: "Z_0",
    },
    Equation {
        axis: "p",
        equation: "ṗ = L_p p + L_v v + L_lat δlat + L_lon δlon + L_0",
        lhs_unit: "rad/s²",
        terms: &[
            (Term::State(P), "L_p", "1/s"),
            (Term::State(V), "L_v", PER_SPEED_ANG),
            (Term::Stick(LAT), "L_lat", PER_STICK_ANG),
            (Term::Stick(LON), "L_lon", PER_STICK_ANG),
        ],
        intercept: "L_0",
    },
    Equation {
        axis: "q",
        equation: "q̇ = M_q q + M_u u + M_lon δlon + M_lat δlat + M_0",
        lhs_unit: "rad/s²",
        terms: &[
            (Term::State(Q), "M_q", "1/s"),
            (Term::State(U), "M_u", PER_SPEED_ANG),
            (Term::Stick(LON), "M_lon", PER_STICK_ANG),
            (Term::Stick(LAT), "M_lat", PER_STICK_ANG),
        ],
        intercept: "M_0",
    },
    Equation {
        axis: "r",
        equation: "ṙ = N_r r + N_v v + N_ped δped + N_col δcol + N_0",
        lhs_unit: "rad/s²",
        terms: &[
            (Term::State(R), "N_r", "1/s"),
            (Term::State(V), "N_v", PER_SPEED_ANG),
            (Term::Stick(PED), "N_ped", PER_STICK_ANG),
            (Term::Stick(COL), "N_col", PER_STICK_ANG),
        ],
        intercept: "N_0",
    },
];

/// Rate axes: name, equation index, damping symbol, control symbol.
pub(super) const RATE_AXES: [(&str, usize, &str, &str); 3] = [
    ("roll", 3, "L_p", "L_lat"),
    ("pitch", 4, "M_q", "M_lon"),
    ("yaw", 5, "N_r", "N_ped"),
];
