//! What can fail when an identifier variant is built, warm started and evaluated.

/// Why parameters (a `params-<variant>.json`) do not fit an identifier; nothing was loaded.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[non_exhaustive]
pub enum ParametersError {
    /// The file has no entry for one of the identifier's models.
    #[error("no parameters for model `{0}`")]
    MissingModel(&'static str),
    /// `algorithm` is neither `covariance` nor `ud`.
    #[error("model {model}: unknown algorithm `{algorithm}`")]
    UnknownAlgorithm {
        /// The model's name.
        model: String,
        /// The algorithm named in the file.
        algorithm: String,
    },
    /// θ or the covariance (U-D) factor has another length than this identifier's model.
    #[error("model {model}: {found} {what}, this identifier has {expected}")]
    Length {
        /// The model's name.
        model: String,
        /// "parameters" (θ) or "covariance entries" (the factor).
        what: &'static str,
        /// Entries in the file.
        found: usize,
        /// Entries the model has.
        expected: usize,
    },
    /// A locally learnt model's rules do not match the identifier's.
    #[error(
        "model {model}: {theta} parameters, {factor} covariance entries and {rule_counts} rule \
         counts; this identifier has {rules} rules of {per_rule} parameters and {factor_per_rule} \
         entries"
    )]
    RuleLayout {
        /// The model's name.
        model: String,
        /// θ entries in the file.
        theta: usize,
        /// Factor entries in the file.
        factor: usize,
        /// Per-rule update counts in the file.
        rule_counts: usize,
        /// Rules of the model.
        rules: usize,
        /// θ_i entries per rule.
        per_rule: usize,
        /// Factor entries per rule.
        factor_per_rule: usize,
    },
    /// The sizes fit but the core rejected the values (e.g. non-finite, not positive definite).
    #[error("the core rejected the parameters")]
    Rejected(#[source] rotorid::Error),
}

/// Why [`evaluate`](super::evaluate) could not evaluate a variant.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[non_exhaustive]
pub enum EvaluateError {
    /// The variant's identifier could not be built (configuration or premise sets).
    #[error("{variant}: cannot build the identifier")]
    Build {
        /// The variant's name.
        variant: &'static str,
        /// The core's reason.
        #[source]
        source: rotorid::Error,
    },
    /// The warm-start parameters do not fit the variant.
    #[error("{variant}: warm start")]
    WarmStart {
        /// The variant's name.
        variant: &'static str,
        /// What does not fit.
        #[source]
        source: ParametersError,
    },
    /// The warm-start parameters predict the training log absurdly (a corrupt or foreign
    /// params file): refused before anything is learnt from them.
    #[error("{variant}: warm start refused: its one-step {state} error on the training log is {error:.3e}, against {hold:.3e} for holding the measured value (more than {ratio}× worse, or not finite): the parameters are not this helicopter's, or the file is damaged")]
    WarmStartAbsurd {
        /// The variant's name.
        variant: &'static str,
        /// The state (`v_x (m/s)` …).
        state: &'static str,
        /// The warm-started model's mean absolute one-step error.
        error: f64,
        /// The hold predictor's.
        hold: f64,
        /// [`WARM_START_MAX_RATIO`](super::WARM_START_MAX_RATIO).
        ratio: f64,
    },
    /// The gyro noise was refused (not finite, negative or beyond the rate range).
    #[error("{variant}: cannot compensate for the gyro noise")]
    Compensate {
        /// The variant's name.
        variant: &'static str,
        /// The core's reason.
        #[source]
        source: rotorid::Error,
    },
    /// The observer's gain was refused (not finite, or outside [0, 1]).
    #[error("{variant}: cannot build the one-step observer")]
    Observer {
        /// The variant's name.
        variant: &'static str,
        /// The core's reason.
        #[source]
        source: rotorid::Error,
    },
}
