//! The lossless wire form of `rotorid`'s [`Error`] (inside [`IdOutput`](super::ident::IdOutput)).
//!
//! 28 bytes: a code per error kind, a detail code per [`Quantity`] or [`ConfigError`], an
//! index and three u64 arguments. Only the canonical encoding (unused fields zero) reads back.

use crate::payload::{Field, PayloadError, Reader, Writer};
use rotorid::error::{ConfigError, Error, Quantity, SampleField};

/// Bytes of an encoded [`Error`] (see [`write_error`]).
pub const ERROR_LEN: usize = 28;

/// The `code` (or `detail`) sent for an error, quantity or configuration error that a newer
/// `rotorid` defines and this protocol version cannot name (`rotorid`'s error enums are
/// `#[non_exhaustive]`). A reader refuses it as an invalid payload.
pub const UNKNOWN_CODE: u8 = 255;

fn quantity_code(q: Quantity) -> (u8, u16) {
    match q {
        Quantity::Sample(SampleField::Roll) => (1, 0),
        Quantity::Sample(SampleField::Pitch) => (2, 0),
        Quantity::Sample(SampleField::Yaw) => (3, 0),
        Quantity::Sample(SampleField::Velocity(i)) => (4, u16::from(i)),
        Quantity::Sample(SampleField::Rate(i)) => (5, u16::from(i)),
        Quantity::Sample(SampleField::Control(i)) => (6, u16::from(i)),
        Quantity::Sample(SampleField::Time) => (7, 0),
        Quantity::Premise(i) => (8, u16::from(i)),
        Quantity::Regressor(i) => (9, i),
        Quantity::Target(i) => (10, u16::from(i)),
        Quantity::Parameter(i) => (11, i),
        Quantity::Covariance(i) => (12, i),
        Quantity::Config => (13, 0),
        // A quantity of a newer core than this protocol version knows.
        _ => (UNKNOWN_CODE, 0),
    }
}

fn quantity_from(code: u8, index: u16) -> Option<Quantity> {
    let small = u8::try_from(index).ok();
    Some(match code {
        1 => SampleField::Roll.into(),
        2 => SampleField::Pitch.into(),
        3 => SampleField::Yaw.into(),
        4 => SampleField::Velocity(small?).into(),
        5 => SampleField::Rate(small?).into(),
        6 => SampleField::Control(small?).into(),
        7 => SampleField::Time.into(),
        8 => Quantity::Premise(small?),
        9 => Quantity::Regressor(index),
        10 => Quantity::Target(small?),
        11 => Quantity::Parameter(index),
        12 => Quantity::Covariance(index),
        13 => Quantity::Config,
        _ => return None,
    })
}

fn config_code(c: ConfigError) -> (u8, u16, u64) {
    let pair = |a: u8, b: u8| u16::from(a) | (u16::from(b) << 8);
    match c {
        ConfigError::MembershipFunction { variable, set } => (1, pair(variable, set), 0),
        ConfigError::RuleCount { expected, found } => (2, expected, u64::from(found)),
        ConfigError::Dimensions => (3, 0, 0),
        ConfigError::InitialCovariance => (4, 0, 0),
        ConfigError::Forgetting => (5, 0, 0),
        ConfigError::ConsequentTerms { needed, found } => (6, pair(needed, found), 0),
        ConfigError::SamplePeriod => (7, 0, 0),
        ConfigError::Sweep => (8, 0, 0),
        ConfigError::Scale => (9, 0, 0),
        ConfigError::ObserverGain { index } => (10, u16::from(index), 0),
        _ => (UNKNOWN_CODE, 0, 0),
    }
}

fn config_from(code: u8, index: u16, a: u64) -> Option<ConfigError> {
    let [lo, hi] = index.to_le_bytes();
    Some(match code {
        1 => ConfigError::MembershipFunction {
            variable: lo,
            set: hi,
        },
        2 => ConfigError::RuleCount {
            expected: index,
            found: u32::try_from(a).ok()?,
        },
        3 => ConfigError::Dimensions,
        4 => ConfigError::InitialCovariance,
        5 => ConfigError::Forgetting,
        6 => ConfigError::ConsequentTerms {
            needed: lo,
            found: hi,
        },
        7 => ConfigError::SamplePeriod,
        8 => ConfigError::Sweep,
        9 => ConfigError::Scale,
        10 if hi == 0 => ConfigError::ObserverGain { index: lo },
        _ => return None,
    })
}

/// Writes `Option<Error>` in [`ERROR_LEN`] bytes, losslessly: `code u8` (0 none, 1 NonFinite,
/// 2 OutOfRange, 3 TimeStep, 4 NonMonotonicTime, 5 Config, 6 Incompatible, 7 Numerical),
/// `detail u8` (the [`Quantity`] or [`ConfigError`] code), `index u16`, then three u64
/// (`TimeStep`: `dt_us, min_us, max_us`; `RuleCount`: `found` in the first; otherwise 0).
pub fn write_error(w: &mut Writer<'_>, e: Option<&Error>) -> Result<(), PayloadError> {
    let (code, detail, index, a, b, c) = match e {
        None => (0, 0, 0, 0, 0, 0),
        Some(Error::NonFinite(q)) => {
            let (d, i) = quantity_code(*q);
            (1, d, i, 0, 0, 0)
        }
        Some(Error::OutOfRange(q)) => {
            let (d, i) = quantity_code(*q);
            (2, d, i, 0, 0, 0)
        }
        Some(Error::TimeStep {
            dt_us,
            min_us,
            max_us,
        }) => (3, 0, 0, *dt_us, *min_us, *max_us),
        Some(Error::NonMonotonicTime) => (4, 0, 0, 0, 0, 0),
        Some(Error::Config(cfg)) => {
            let (d, i, a) = config_code(*cfg);
            (5, d, i, a, 0, 0)
        }
        Some(Error::Incompatible) => (6, 0, 0, 0, 0, 0),
        Some(Error::Numerical) => (7, 0, 0, 0, 0, 0),
        Some(_) => (UNKNOWN_CODE, 0, 0, 0, 0, 0),
    };
    if w.remaining() < ERROR_LEN {
        return Err(PayloadError::Overflow {
            needed: ERROR_LEN,
            remaining: w.remaining(),
        });
    }
    w.put_u8(code)?;
    w.put_u8(detail)?;
    w.put_u16(index)?;
    w.put_u64(a)?;
    w.put_u64(b)?;
    w.put_u64(c)
}

/// Reads what [`write_error`] wrote. Unknown codes are [`PayloadError::InvalidValue`].
pub fn read_error(r: &mut Reader<'_>) -> Result<Option<Error>, PayloadError> {
    let bytes = r.get_bytes(ERROR_LEN)?;
    let mut r = Reader::new(bytes);
    let (code, detail, index) = (r.get_u8()?, r.get_u8()?, r.get_u16()?);
    let (a, b, c) = (r.get_u64()?, r.get_u64()?, r.get_u64()?);
    let bad = PayloadError::InvalidValue;
    let error = decode_error(code, detail, index, [a, b, c])?;
    // Only the canonical encoding is accepted (unused fields zero), so that every accepted
    // payload writes back to the same bytes: re-encode and compare.
    let mut again = [0u8; ERROR_LEN];
    write_error(&mut Writer::new(&mut again), error.as_ref())?;
    if again.as_slice() != bytes {
        return Err(bad);
    }
    Ok(error)
}

/// The error of a decoded `code, detail, index, [a, b, c]`.
fn decode_error(
    code: u8,
    detail: u8,
    index: u16,
    [a, b, c]: [u64; 3],
) -> Result<Option<Error>, PayloadError> {
    let bad = PayloadError::InvalidValue;
    Ok(Some(match code {
        0 => return Ok(None),
        1 => Error::NonFinite(quantity_from(detail, index).ok_or(bad)?),
        2 => Error::OutOfRange(quantity_from(detail, index).ok_or(bad)?),
        3 => Error::TimeStep {
            dt_us: a,
            min_us: b,
            max_us: c,
        },
        4 => Error::NonMonotonicTime,
        5 => Error::Config(config_from(detail, index, a).ok_or(bad)?),
        6 => Error::Incompatible,
        7 => Error::Numerical,
        _ => return Err(bad),
    }))
}

/// `Option<Error>` travels as [`write_error`] writes it.
impl Field for Option<Error> {
    const LEN: usize = ERROR_LEN;
    fn put(&self, w: &mut Writer<'_>) -> Result<(), PayloadError> {
        write_error(w, self.as_ref())
    }
    fn get(r: &mut Reader<'_>) -> Result<Self, PayloadError> {
        read_error(r)
    }
}

#[cfg(test)]
mod tests {
    extern crate alloc;
    use super::*;
    use alloc::vec;
    use alloc::vec::Vec;

    fn written(e: Option<&Error>) -> Vec<u8> {
        let mut buf = [0u8; ERROR_LEN];
        let mut w = Writer::new(&mut buf);
        write_error(&mut w, e).unwrap();
        w.written().to_vec()
    }

    fn all_errors() -> Vec<Option<Error>> {
        let qs = [
            Quantity::Sample(SampleField::Roll),
            Quantity::Sample(SampleField::Pitch),
            Quantity::Sample(SampleField::Yaw),
            Quantity::Sample(SampleField::Velocity(2)),
            Quantity::Sample(SampleField::Rate(1)),
            Quantity::Sample(SampleField::Control(3)),
            Quantity::Sample(SampleField::Time),
            Quantity::Premise(2),
            Quantity::Regressor(1484),
            Quantity::Target(2),
            Quantity::Parameter(53),
            Quantity::Covariance(1484),
            Quantity::Config,
        ];
        let cs = [
            ConfigError::MembershipFunction {
                variable: 2,
                set: 1,
            },
            ConfigError::RuleCount {
                expected: 27,
                found: 70_000,
            },
            ConfigError::Dimensions,
            ConfigError::InitialCovariance,
            ConfigError::Forgetting,
            ConfigError::ConsequentTerms {
                needed: 3,
                found: 2,
            },
            ConfigError::SamplePeriod,
            ConfigError::Sweep,
            ConfigError::Scale,
            ConfigError::ObserverGain { index: 5 },
        ];
        let mut v = vec![
            None,
            Some(Error::TimeStep {
                dt_us: u64::MAX,
                min_us: 10_000,
                max_us: 30_000,
            }),
            Some(Error::NonMonotonicTime),
            Some(Error::Incompatible),
            Some(Error::Numerical),
        ];
        for q in qs {
            v.push(Some(Error::NonFinite(q)));
            v.push(Some(Error::OutOfRange(q)));
        }
        for c in cs {
            v.push(Some(Error::Config(c)));
        }
        v
    }

    #[test]
    fn every_error_roundtrips() {
        for e in all_errors() {
            let b = written(e.as_ref());
            assert_eq!(b.len(), ERROR_LEN);
            assert_eq!(read_error(&mut Reader::new(&b)), Ok(e));
            for n in 0..ERROR_LEN {
                assert!(read_error(&mut Reader::new(&b[..n])).is_err());
            }
        }
        let mut b = [0u8; ERROR_LEN];
        b[0] = 8;
        assert_eq!(
            read_error(&mut Reader::new(&b)),
            Err(PayloadError::InvalidValue)
        );
        b[0] = 1;
        b[1] = 14;
        assert!(read_error(&mut Reader::new(&b)).is_err());
        b[1] = 4;
        b[2] = 0;
        b[3] = 1; // Velocity(256) does not fit a u8
        assert!(read_error(&mut Reader::new(&b)).is_err());
        // A writer without room writes nothing.
        let mut small = [0u8; 10];
        let mut w = Writer::new(&mut small);
        assert!(write_error(&mut w, Some(&Error::Numerical)).is_err());
        assert!(w.is_empty());
    }
}
