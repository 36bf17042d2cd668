//! Parameter dumps and the export/import snapshot stream of the onboard identifiers.

use super::{Ident, MsgType, Payload};
use crate::{Field, PayloadError, Reader, Writer};
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
    pub const MAX_WORDS: usize = (crate::MAX_PAYLOAD - Self::HEADER) / 4;
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

/// `ExportChunk` / `ImportChunk` payload (13 B + data): ident u8, offset u32 (of the first data
/// byte in the snapshot stream), total u32 (stream length), crc u32 (CRC-32/ISO-HDLC of the
/// whole stream, the same in every chunk), then up to [`DataChunk::MAX_DATA`] bytes. Chunks
/// travel in order; the receiver checks offsets, length and CRC before it uses the stream.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct DataChunk<'a> {
    /// Which identifier.
    pub ident: Ident,
    /// Offset of `data` in the stream.
    pub offset: u32,
    /// Stream length, in bytes.
    pub total: u32,
    /// CRC-32 of the whole stream.
    pub crc: u32,
    /// The bytes.
    pub data: &'a [u8],
}

impl<'a> DataChunk<'a> {
    /// Header bytes.
    pub const HEADER: usize = 13;
    /// Most data bytes in one chunk.
    pub const MAX_DATA: usize = crate::MAX_PAYLOAD - Self::HEADER;
}

impl<'a> Payload<'a> for DataChunk<'a> {
    const TYPES: &'static [MsgType] = &[MsgType::ExportChunk, MsgType::ImportChunk];

    fn encoded_len(&self) -> usize {
        Self::HEADER + self.data.len()
    }

    fn put_fields(&self, w: &mut Writer<'_>) -> Result<(), PayloadError> {
        if self.data.len() > Self::MAX_DATA {
            return Err(PayloadError::InvalidValue);
        }
        self.ident.put(w)?;
        w.put_u32(self.offset)?;
        w.put_u32(self.total)?;
        w.put_u32(self.crc)?;
        w.put_bytes(self.data)
    }

    fn get_fields(r: &mut Reader<'a>) -> Result<Self, PayloadError> {
        let ident = Field::get(r)?;
        let offset = r.get_u32()?;
        let total = r.get_u32()?;
        let crc = r.get_u32()?;
        let data = r.get_bytes(r.remaining())?;
        let end = u64::from(offset) + data.len() as u64;
        if data.len() > Self::MAX_DATA || end > u64::from(total) {
            return Err(PayloadError::InvalidValue);
        }
        Ok(Self {
            ident,
            offset,
            total,
            crc,
            data,
        })
    }
}

/// CRC-32/ISO-HDLC of a byte stream (the frame CRC), for [`DataChunk::crc`].
pub fn stream_crc(bytes: &[u8]) -> u32 {
    crate::CRC.checksum(bytes)
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

/// Bytes of one estimator in the snapshot stream: algorithm u8, updates u32, θ, factor (f32
/// each).
pub fn model_len(model: &RlsView<'_, f32>) -> usize {
    state_len(model.len(), model.packed_factor().len())
}

/// Bytes of one estimator's part of the snapshot stream, from its sizes: algorithm u8,
/// updates u32, then `parameters` θ and `factor_len` packed factor entries as f32 (all
/// little-endian). `const`, so that a receiver can size its buffers from
/// [`RlsState::PARAMETERS`] and [`RlsState::FACTOR_LEN`].
pub const fn state_len(parameters: usize, factor_len: usize) -> usize {
    5 + 4 * (parameters + factor_len)
}

/// Byte `i` of one estimator's part of the snapshot stream (0 past its end).
fn model_byte(model: &RlsView<'_, f32>, i: usize) -> u8 {
    let word = |xs: &[f32], j: usize| {
        xs.get(j / 4)
            .and_then(|v| v.to_bits().to_le_bytes().get(j % 4).copied())
            .unwrap_or(0)
    };
    match i {
        0 => model.algorithm().code(),
        1..=4 => model
            .counters()
            .updates
            .to_le_bytes()
            .get(i - 1)
            .copied()
            .unwrap_or(0),
        _ => {
            let j = i - 5;
            let t = 4 * model.len();
            if j < t {
                word(model.parameters(), j)
            } else {
                word(model.packed_factor(), j - t)
            }
        }
    }
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

/// Length of the snapshot stream of `models`.
pub fn snapshot_len(models: &[RlsView<'_, f32>]) -> usize {
    models.iter().map(model_len).sum()
}

/// Copies the snapshot stream of `models` (each model's bytes, in order) from `offset` into
/// `out`; returns the bytes written (fewer than `out.len()` at the end of the stream).
pub fn snapshot_read(models: &[RlsView<'_, f32>], offset: usize, out: &mut [u8]) -> usize {
    let mut start = 0usize;
    let mut n = 0usize;
    for m in models {
        let len = model_len(m);
        while n < out.len() && offset + n < start + len {
            let pos = offset + n;
            if pos >= start {
                if let Some(o) = out.get_mut(n) {
                    *o = model_byte(m, pos - start);
                }
                n += 1;
            } else {
                break;
            }
        }
        start += len;
    }
    n
}

/// CRC-32 of the snapshot stream of `models` (computed piecewise, without a stream buffer).
pub fn snapshot_crc(models: &[RlsView<'_, f32>]) -> u32 {
    let mut digest = crate::CRC.digest();
    let mut buf = [0u8; 64];
    let mut offset = 0;
    loop {
        let n = snapshot_read(models, offset, &mut buf);
        if n == 0 {
            break;
        }
        digest.update(buf.get(..n).unwrap_or_default());
        offset += n;
    }
    digest.finalize()
}

/// An [`RlsState`]'s fields as slices, so that one [`StateDecoder`] serves every model size.
#[derive(Debug)]
pub struct StateParts<'a> {
    /// The RLS form.
    pub algorithm: &'a mut Algorithm,
    /// The update counter.
    pub updates: &'a mut u32,
    /// θ (scaled coordinates).
    pub theta: &'a mut [f32],
    /// The packed covariance or U-D factor.
    pub factor: &'a mut [f32],
}

impl<'a, const N: usize, const NP: usize> From<&'a mut RlsState<f32, N, NP>> for StateParts<'a> {
    fn from(s: &'a mut RlsState<f32, N, NP>) -> Self {
        Self {
            algorithm: &mut s.algorithm,
            updates: &mut s.updates,
            theta: &mut s.theta,
            factor: &mut s.factor,
        }
    }
}

/// Rebuilds one model's [`RlsState`] from its snapshot-stream bytes, one byte at a time (the
/// inverse of what [`snapshot_read`] writes), for a receiver that cannot stage a whole stream:
/// the firmware decodes the fuzzy identifier's 10.5 KiB import straight into one model's
/// staging state. [`read_rls_state`] is the same from a buffer.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct StateDecoder {
    pos: usize,
    word: [u8; 4],
}

impl StateDecoder {
    /// A decoder at the start of a model.
    pub const fn new() -> Self {
        Self {
            pos: 0,
            word: [0; 4],
        }
    }

    /// Bytes taken so far.
    pub fn position(&self) -> usize {
        self.pos
    }

    /// Whether the model whose fields are `parts` is complete.
    pub fn is_complete(&self, parts: &StateParts<'_>) -> bool {
        self.pos == state_len(parts.theta.len(), parts.factor.len())
    }

    /// Takes the next byte into `parts`. Errors, with nothing taken:
    /// [`PayloadError::InvalidValue`] for an unknown algorithm code,
    /// [`PayloadError::TrailingBytes`] past the end of the model.
    pub fn push(&mut self, parts: StateParts<'_>, byte: u8) -> Result<(), PayloadError> {
        let StateParts {
            algorithm,
            updates,
            theta,
            factor,
        } = parts;
        match self.pos {
            0 => *algorithm = Algorithm::from_code(byte).ok_or(PayloadError::InvalidValue)?,
            1..=4 => {
                let shift = 8 * (self.pos - 1);
                *updates = (*updates & !(0xff << shift)) | (u32::from(byte) << shift);
            }
            pos => {
                let i = (pos - 5) / 4;
                let slot = match theta.len() {
                    n if i < n => theta.get_mut(i),
                    n => factor.get_mut(i - n),
                };
                let Some(slot) = slot else {
                    return Err(PayloadError::TrailingBytes { extra: 1 });
                };
                let k = (pos - 5) % 4;
                if let Some(w) = self.word.get_mut(k) {
                    *w = byte;
                }
                if k == 3 {
                    *slot = f32::from_le_bytes(self.word);
                }
            }
        }
        self.pos += 1;
        Ok(())
    }
}

/// Reads one model's state (as written by the snapshot stream) into an [`RlsState`].
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
    use super::super::testing::roundtrip;
    use super::*;
    use alloc::vec;
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

        let data = [9u8; DataChunk::MAX_DATA];
        let d = DataChunk {
            ident: Ident::Plain,
            offset: 7,
            total: 7 + DataChunk::MAX_DATA as u32,
            crc: 0xDEAD_BEEF,
            data: &data,
        };
        let b = roundtrip(&d);
        assert_eq!(b.len(), crate::MAX_PAYLOAD);
        assert_eq!(DataChunk::read(&b), Ok(d));
        for n in 0..DataChunk::HEADER {
            assert!(DataChunk::read(&b[..n]).is_err());
        }
        let mut bad = b;
        bad[5] = 0; // total < offset + len
        assert!(DataChunk::read(&bad).is_err());
    }

    #[test]
    fn snapshot_stream_reads_back_exactly() {
        use rotorid::{Rls, RlsConfig};
        let mut a = Rls::<f32, 2, 3>::new(RlsConfig::default()).unwrap();
        for k in 0..77 {
            let x = k as f32;
            a.update(&[1.0, 0.1 * x], 0.5 - 0.2 * x).unwrap();
        }
        let mut b = Rls::<f32, 1, 1>::new(RlsConfig::paper(10.0)).unwrap();
        b.update(&[2.0], 1.0).unwrap();
        let (theta, factor) = (*a.parameters(), *a.packed_factor());
        let views = [a.view(), b.view()];
        let len = snapshot_len(&views);
        assert_eq!(len, 25 + 13);
        // Read in odd-sized pieces; must equal one big read.
        let mut whole = vec![0u8; len + 5];
        assert_eq!(snapshot_read(&views, 0, &mut whole), len);
        whole.truncate(len);
        let mut pieces = Vec::new();
        let mut off = 0;
        loop {
            let mut buf = [0u8; 7];
            let n = snapshot_read(&views, off, &mut buf);
            if n == 0 {
                break;
            }
            pieces.extend_from_slice(&buf[..n]);
            off += n;
        }
        assert_eq!(pieces, whole);
        assert_eq!(snapshot_crc(&views), stream_crc(&whole));
        let mut r = Reader::new(&whole);
        let a = read_rls_state::<2, 3>(&mut r).unwrap();
        assert_eq!(
            (a.algorithm, a.updates, a.theta, a.factor),
            (Algorithm::UdFactor, 77, theta, factor)
        );
        let b = read_rls_state::<1, 1>(&mut r).unwrap();
        assert_eq!((b.algorithm, b.updates), (Algorithm::Covariance, 1));
        assert_eq!(r.finish(), Ok(()));
        assert!(read_rls_state::<2, 3>(&mut Reader::new(&whole[..20])).is_err());
        let mut bad = whole.clone();
        bad[0] = 2;
        assert!(read_rls_state::<2, 3>(&mut Reader::new(&bad)).is_err());

        // Byte by byte, the stream decoder rebuilds the same states.
        fn blank<const N: usize, const NP: usize>() -> RlsState<f32, N, NP> {
            RlsState {
                algorithm: Algorithm::Covariance,
                theta: [0.0; N],
                factor: [0.0; NP],
                updates: 0,
            }
        }
        let mut first = blank::<2, 3>();
        let mut second = blank::<1, 1>();
        let (mut d1, mut d2) = (StateDecoder::new(), StateDecoder::new());
        for &byte in &whole {
            if !d1.is_complete(&StateParts::from(&mut first)) {
                d1.push(StateParts::from(&mut first), byte).unwrap();
            } else {
                d2.push(StateParts::from(&mut second), byte).unwrap();
            }
        }
        assert!(d2.is_complete(&StateParts::from(&mut second)));
        assert_eq!(first, a);
        assert_eq!(second, b);
        assert_eq!(d1.position(), state_len(2, 3));
        // Past the end, and an unknown algorithm code: refused, nothing taken.
        let before = second;
        assert_eq!(
            d2.push(StateParts::from(&mut second), 0),
            Err(PayloadError::TrailingBytes { extra: 1 })
        );
        assert_eq!((second, d2.position()), (before, state_len(1, 1)));
        let mut d = StateDecoder::new();
        assert_eq!(
            d.push(StateParts::from(&mut second), 2),
            Err(PayloadError::InvalidValue)
        );
        assert_eq!((second, d.position()), (before, 0));
    }
}
