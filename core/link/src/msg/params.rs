//! Parameter dumps of the onboard identifiers (`Params`), and the raw estimator-state reader
//! the fuzz targets feed to the core's import checks.

use super::ident::Ident;
use super::message::{MsgType, Payload};
use crate::payload::{Field, PayloadError, Reader, Writer};
use rotorid::rls::{Algorithm, RlsState, RlsView};

wire_enum! {
    /// Which vector a [`ParamsChunk`] carries.
    #[non_exhaustive]
    #[derive(Clone, Copy, Debug, PartialEq, Eq)]
    #[cfg_attr(feature = "defmt", derive(defmt::Format))]
    pub enum ParamField {
        /// θ (f32 bits), N words.
        Theta = 0,
        /// diag(P) (f32 bits), N words.
        CovarianceDiagonal = 1,
        /// [`ParamsChunk::SUMMARY_WORDS`] words: trace(P) (f32 bits), updates, windup guards,
        /// last innovation (f32 bits), algorithm (0 covariance, 1 U-D).
        Summary = 2,
    }
}

/// `Params` payload (7 B + 4 B per word): ident u8, model u8 (0 velocity, 1 q̂, 2 r̂, 3 p̂),
/// field u8 ([`ParamField`]), index u16 of the first word, total u16 (words in the field),
/// then up to [`ParamsChunk::MAX_WORDS`] u32 words. A dump is, for each model in order, θ,
/// diag(P) and the summary, each in as many chunks as needed; it ends with model 3's summary.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct ParamsChunk<'a> {
    /// Which identifier.
    pub ident: Ident,
    /// Model index: 0 velocity, 1 q̂, 2 r̂, 3 p̂.
    pub model: u8,
    /// What the words are.
    pub field: ParamField,
    /// Index of the first word within the field.
    pub index: u16,
    /// Words in the whole field.
    pub total: u16,
    /// The words, little-endian u32 each (length a multiple of 4).
    pub words: &'a [u8],
}

impl<'a> ParamsChunk<'a> {
    /// Header bytes.
    pub const HEADER: usize = 7;
    /// Most words in one chunk.
    pub const MAX_WORDS: usize = (crate::wire::MAX_PAYLOAD - Self::HEADER) / 4;
    /// Words of a [`ParamField::Summary`].
    pub const SUMMARY_WORDS: usize = 5;

    /// The words as u32.
    pub fn iter(&self) -> impl Iterator<Item = u32> + 'a {
        self.words
            .chunks_exact(4)
            .map(|c| u32::from_le_bytes(c.try_into().unwrap_or([0; 4])))
    }
}

impl<'a> Payload<'a> for ParamsChunk<'a> {
    const TYPES: &'static [MsgType] = &[MsgType::Params];

    fn encoded_len(&self) -> usize {
        Self::HEADER + self.words.len()
    }

    fn put_fields(&self, w: &mut Writer<'_>) -> Result<(), PayloadError> {
        if !self.words.len().is_multiple_of(4) || self.words.len() / 4 > Self::MAX_WORDS {
            return Err(PayloadError::InvalidValue);
        }
        self.ident.put(w)?;
        w.put_u8(self.model)?;
        self.field.put(w)?;
        w.put_u16(self.index)?;
        w.put_u16(self.total)?;
        w.put_bytes(self.words)
    }

    fn get_fields(r: &mut Reader<'a>) -> Result<Self, PayloadError> {
        let ident = Field::get(r)?;
        let model = r.get_u8()?;
        let field = Field::get(r)?;
        let index = r.get_u16()?;
        let total = r.get_u16()?;
        let words = r.get_bytes(r.remaining())?;
        let n = words.len() / 4;
        if model > 3
            || !words.len().is_multiple_of(4)
            || n > Self::MAX_WORDS
            || usize::from(index) + n > usize::from(total)
        {
            return Err(PayloadError::InvalidValue);
        }
        Ok(Self {
            ident,
            model,
            field,
            index,
            total,
            words,
        })
    }
}

/// The `Summary` words of one estimator in `Params` ([`ParamField::Summary`]): trace(P) as
/// f32 bits, updates, windup guards, numerical skips, and the algorithm's code.
pub fn summary_words(model: &RlsView<'_, f32>) -> [u32; ParamsChunk::SUMMARY_WORDS] {
    let c = model.counters();
    [
        model.trace().to_bits(),
        c.updates,
        c.windup_guards,
        c.numerical_skips,
        u32::from(model.algorithm().code()),
    ]
}

/// The covariance form travels as one byte: 0 covariance, 1 U-D.
impl Field for Algorithm {
    const LEN: usize = 1;
    fn put(&self, w: &mut Writer<'_>) -> Result<(), PayloadError> {
        w.put_u8(self.code())
    }
    fn get(r: &mut Reader<'_>) -> Result<Self, PayloadError> {
        Algorithm::from_code(r.get_u8()?).ok_or(PayloadError::InvalidValue)
    }
}

/// Reads one estimator's state from a compact byte form (algorithm u8, updates u32, θ, packed
/// factor as f32, little-endian) into an [`RlsState`]. Not a link message since protocol
/// version 2 (export and import carry the core's snapshot, [`super::snapshot`]): the
/// `parameter_import` fuzz target and its regression test build arbitrary states with it.
pub fn read_rls_state<const N: usize, const NP: usize>(
    r: &mut Reader<'_>,
) -> Result<RlsState<f32, N, NP>, PayloadError> {
    Ok(RlsState {
        algorithm: Field::get(r)?,
        updates: r.get_u32()?,
        theta: Field::get(r)?,
        factor: Field::get(r)?,
    })
}

#[cfg(test)]
mod tests {
    extern crate alloc;
    use super::super::message::testing::roundtrip;
    use super::*;
    use alloc::vec::Vec;

    #[test]
    fn chunks_roundtrip_and_check_bounds() {
        let words: Vec<u8> = (0..8u8).collect();
        let c = ParamsChunk {
            ident: Ident::Fuzzy,
            model: 3,
            field: ParamField::Summary,
            index: 0,
            total: 2,
            words: &words,
        };
        let b = roundtrip(&c);
        assert_eq!(ParamsChunk::read(&b), Ok(c));
        assert_eq!(c.iter().collect::<Vec<_>>(), [0x0302_0100, 0x0706_0504]);
        for n in 0..ParamsChunk::HEADER {
            assert!(ParamsChunk::read(&b[..n]).is_err());
        }
        assert!(
            ParamsChunk::read(&b[..b.len() - 1]).is_err(),
            "partial word"
        );
        let mut bad = b.clone();
        bad[1] = 4; // model
        assert!(ParamsChunk::read(&bad).is_err());
        let mut bad = b.clone();
        bad[5] = 1; // total 1 < index + words
        assert!(ParamsChunk::read(&bad).is_err());
        let too_many = [0u8; 4 * (ParamsChunk::MAX_WORDS + 1)];
        let mut buf = [0u8; 300];
        let big = ParamsChunk {
            words: &too_many,
            total: 1000,
            ..c
        };
        assert!(big.write(&mut Writer::new(&mut buf)).is_err());
    }

    #[test]
    fn raw_state_reads_back_exactly() {
        use rotorid::rls::{Rls, RlsConfig};
        let mut a = Rls::<f32, 2, 3>::new(RlsConfig::default()).unwrap();
        for k in 0..77 {
            let x = k as f32;
            a.update(&[1.0, 0.1 * x], 0.5 - 0.2 * x).unwrap();
        }
        let mut bytes = Vec::from([1u8]);
        bytes.extend_from_slice(&77u32.to_le_bytes());
        for x in a.parameters().iter().chain(a.packed_factor()) {
            bytes.extend_from_slice(&x.to_bits().to_le_bytes());
        }
        let mut r = Reader::new(&bytes);
        let s = read_rls_state::<2, 3>(&mut r).unwrap();
        assert_eq!(r.finish(), Ok(()));
        assert_eq!(
            (s.algorithm, s.updates, s.theta, s.factor),
            (Algorithm::UdFactor, 77, *a.parameters(), *a.packed_factor())
        );
        assert!(read_rls_state::<2, 3>(&mut Reader::new(&bytes[..20])).is_err());
        let mut bad = bytes.clone();
        bad[0] = 2; // no such algorithm
        assert!(read_rls_state::<2, 3>(&mut Reader::new(&bad)).is_err());
    }
}
