//! The Python exceptions: `RotoridError` and its subclasses, and the conversions from the
//! Rust errors. Every exception carries `kind` (a short string naming the Rust error's
//! variant), and the message says what to do; none quotes more than a few input characters
//! (the Rust messages are written that way).

use pyo3::create_exception;
use pyo3::exceptions::PyException;
use pyo3::prelude::*;
use rotorid_cli::error_chain::Chain;

create_exception!(
    _rotorid,
    RotoridError,
    PyException,
    "Base of every rotorid error; `kind` names the Rust error's variant."
);
create_exception!(
    _rotorid,
    InputError,
    RotoridError,
    "An argument of a Python call is wrong (dtype, shape, range, unknown name)."
);
create_exception!(
    _rotorid,
    LogError,
    RotoridError,
    "A log could not be read or imported (file, format, columns, values)."
);
create_exception!(
    _rotorid,
    IdentifyError,
    RotoridError,
    "An identification failed (too little data, a failed evaluation, a file not written)."
);
create_exception!(
    _rotorid,
    SimulateError,
    RotoridError,
    "A simulation was refused or diverged."
);
create_exception!(
    _rotorid,
    CoreError,
    RotoridError,
    "The core refused a call (`rotorid::Error`); the subclasses are its variants."
);
create_exception!(
    _rotorid,
    NonFiniteError,
    CoreError,
    "A value is NaN or ±∞ (`rotorid::Error::NonFinite`)."
);
create_exception!(
    _rotorid,
    OutOfRangeError,
    CoreError,
    "A finite value lies outside the accepted range (`rotorid::Error::OutOfRange`)."
);
create_exception!(
    _rotorid,
    TimeStepError,
    CoreError,
    "The time since the previous sample is outside the accepted window (`rotorid::Error::TimeStep`); start a new sample chain with `resume`."
);
create_exception!(
    _rotorid,
    NonMonotonicTimeError,
    CoreError,
    "The time stamp does not increase (`rotorid::Error::NonMonotonicTime`)."
);
create_exception!(
    _rotorid,
    ConfigError,
    CoreError,
    "A configuration was refused (`rotorid::Error::Config`)."
);
create_exception!(
    _rotorid,
    IncompatibleError,
    CoreError,
    "Imported state does not fit: wrong kind, size, version or CRC (`rotorid::Error::Incompatible`)."
);
create_exception!(
    _rotorid,
    NumericalError,
    CoreError,
    "The update would produce a non-finite number; nothing was changed (`rotorid::Error::Numerical`)."
);

/// Adds the exception classes to the module.
pub fn register(m: &Bound<'_, PyModule>) -> PyResult<()> {
    let py = m.py();
    m.add("RotoridError", py.get_type::<RotoridError>())?;
    m.add("InputError", py.get_type::<InputError>())?;
    m.add("LogError", py.get_type::<LogError>())?;
    m.add("IdentifyError", py.get_type::<IdentifyError>())?;
    m.add("SimulateError", py.get_type::<SimulateError>())?;
    m.add("CoreError", py.get_type::<CoreError>())?;
    m.add("NonFiniteError", py.get_type::<NonFiniteError>())?;
    m.add("OutOfRangeError", py.get_type::<OutOfRangeError>())?;
    m.add("TimeStepError", py.get_type::<TimeStepError>())?;
    m.add(
        "NonMonotonicTimeError",
        py.get_type::<NonMonotonicTimeError>(),
    )?;
    m.add("ConfigError", py.get_type::<ConfigError>())?;
    m.add("IncompatibleError", py.get_type::<IncompatibleError>())?;
    m.add("NumericalError", py.get_type::<NumericalError>())?;
    Ok(())
}

/// `err` with its `kind` attribute set.
fn with_kind(err: PyErr, kind: &str) -> PyErr {
    Python::attach(|py| {
        // Setting an attribute on a fresh exception object cannot fail in practice; if it
        // did, the exception still says what went wrong.
        let _ = err.value(py).setattr("kind", kind);
    });
    err
}

/// An argument error.
pub fn input(message: impl Into<String>) -> PyErr {
    with_kind(InputError::new_err(message.into()), "Input")
}

/// The core's error, as its subclass of `CoreError`; `context` (for example "sample 12")
/// goes before the message.
pub fn core(e: rotorid::Error, context: &str) -> PyErr {
    let message = if context.is_empty() {
        e.to_string()
    } else {
        format!("{context}: {e}")
    };
    let (err, kind) = match e {
        rotorid::Error::NonFinite(_) => (NonFiniteError::new_err(message), "NonFinite"),
        rotorid::Error::OutOfRange(_) => (OutOfRangeError::new_err(message), "OutOfRange"),
        rotorid::Error::TimeStep { .. } => (TimeStepError::new_err(message), "TimeStep"),
        rotorid::Error::NonMonotonicTime => {
            (NonMonotonicTimeError::new_err(message), "NonMonotonicTime")
        }
        rotorid::Error::Config(_) => (ConfigError::new_err(message), "Config"),
        rotorid::Error::Incompatible => (IncompatibleError::new_err(message), "Incompatible"),
        rotorid::Error::Numerical => (NumericalError::new_err(message), "Numerical"),
        _ => (CoreError::new_err(message), "Other"),
    };
    with_kind(err, kind)
}

/// A log import error (with its causes).
pub fn log(e: &rotorid_cli::import::ImportError) -> PyErr {
    with_kind(LogError::new_err(Chain(e).to_string()), "Import")
}

/// A CSV read or write error (with its causes).
pub fn csv(e: &rotorid_cli::log::LogError) -> PyErr {
    with_kind(LogError::new_err(Chain(e).to_string()), "Log")
}

/// An identification error (with its causes); a log that cannot be imported is a `LogError`.
pub fn identify(e: &rotorid_cli::identify::IdentifyError) -> PyErr {
    use rotorid_cli::identify::IdentifyError as E;
    let kind = match e {
        E::Import(i) => return log(i),
        E::Window(_) => "Window",
        E::NoLogs => "NoLogs",
        E::NoSamples(_) => "NoSamples",
        E::Split(_) => "Split",
        E::TooFewSamples(_) => "TooFewSamples",
        E::Read { .. } => "Read",
        E::Write { .. } => "Write",
        E::CreateDir { .. } => "CreateDir",
        E::ParseJson { .. } => "ParseJson",
        E::ToJson { .. } => "ToJson",
        E::Evaluate(_) => "Evaluate",
        E::Precision(_) => "Precision",
        E::Figure(_) => "Figure",
        _ => "Other",
    };
    with_kind(IdentifyError::new_err(Chain(e).to_string()), kind)
}

/// A simulation error (with its causes).
pub fn simulate(e: &rotorid_cli::simulate::SimulateError) -> PyErr {
    with_kind(SimulateError::new_err(Chain(e).to_string()), "Simulate")
}
