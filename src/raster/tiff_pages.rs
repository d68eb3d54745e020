//! TIFF pages: the directory chain walked by hand, and each page handed to the `image` crate's TIFF
//! decoder as if it were the file's only image.
//!
//! A TIFF file is a header pointing at the first image file directory (IFD, one per page), each IFD
//! pointing at the next. The codec reads the first page only, so the page to read is made the
//! first one by a [`PatchedReader`] that shows the file with the header's pointer replaced; the
//! file itself is never copied. The same reader clears a Predictor tag on pages whose compression
//! does not define one, which the codec would otherwise apply to already decoded samples (a JPEG
//! page comes out striped) or refuse as corrupt, and shows a JPEG page in YCbCr, which the codec
//! does not take, as RGB whose samples are converted after decoding (see [`page_fix`]).
//!
//! Walking the chain reads two numbers per IFD, and its length is found with Floyd's cycle test,
//! so a hostile chain (thousands of pages, or pages pointing back at each other) costs time
//! proportional to its distinct IFDs and no memory beyond the offsets of the pages kept, which
//! [`crate::Limits::max_pages`] bounds.

use std::io::{self, BufRead, Read, Seek, SeekFrom};

/// Compressions for which a Predictor tag means something: LZW (the only one TIFF 6.0 defines
/// it for), Adobe Deflate and old Deflate, LZMA and ZSTD (the later extensions). Everywhere else
/// (no compression, PackBits, CCITT fax, JPEG) readers ignore the tag, and so do we.
const PREDICTED_COMPRESSIONS: &[u64] = &[5, 8, 32_946, 34_925, 50_000];

const TAG_COMPRESSION: u16 = 259;
const TAG_PHOTOMETRIC: u16 = 262;
const TAG_SAMPLES_PER_PIXEL: u16 = 277;
const TAG_PREDICTOR: u16 = 317;
/// Compression 7: JPEG ("new-style", TIFF Technical Note 2).
const COMPRESSION_JPEG: u64 = 7;
const PHOTOMETRIC_RGB: u64 = 2;
const PHOTOMETRIC_YCBCR: u64 = 6;
/// Field type SHORT (16-bit unsigned).
const TYPE_SHORT: u16 = 3;

/// The parts of a TIFF header that say how to read the rest.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) struct Header {
    /// BigTIFF: 64-bit offsets and counts.
    big: bool,
    little_endian: bool,
    /// Offset of the first IFD.
    pub(crate) first: u64,
}

/// The pages of a TIFF file: the offsets of the IFDs traced, in chain order.
#[derive(Clone, Debug, PartialEq, Eq)]
pub(crate) struct Chain {
    pub(crate) header: Header,
    /// One offset per page, at most the limit asked for.
    pub(crate) pages: Vec<u64>,
    /// Distinct IFDs in the chain (may exceed `pages.len()` when the chain was over the limit).
    pub(crate) count: u64,
    /// The chain does not end with a zero pointer: it points outside the file, at a truncated IFD
    /// or back at an earlier page.
    pub(crate) damaged: bool,
}

impl Header {
    /// The header of `bytes`; `None` when they do not start like a TIFF file.
    pub(crate) fn read(bytes: &[u8]) -> Option<Header> {
        let little_endian = match bytes.get(..2)? {
            b"II" => true,
            b"MM" => false,
            _ => return None,
        };
        let mut header = Header {
            big: false,
            little_endian,
            first: 0,
        };
        match header.u16_at(bytes, 2)? {
            42 => header.first = header.u32_at(bytes, 4)?,
            43 => {
                // BigTIFF: offset size 8, then a reserved zero.
                if header.u16_at(bytes, 4)? != 8 || header.u16_at(bytes, 6)? != 0 {
                    return None;
                }
                header.big = true;
                header.first = header.u64_at(bytes, 8)?;
            }
            _ => return None,
        }
        Some(header)
    }

    fn number_at(&self, bytes: &[u8], at: u64, size: usize) -> Option<u64> {
        let start = usize::try_from(at).ok()?;
        let field = bytes.get(start..start.checked_add(size)?)?;
        let mut value = 0u64;
        for i in 0..size {
            let byte = if self.little_endian {
                field[size - 1 - i]
            } else {
                field[i]
            };
            value = (value << 8) | u64::from(byte);
        }
        Some(value)
    }

    fn u16_at(&self, bytes: &[u8], at: u64) -> Option<u16> {
        self.number_at(bytes, at, 2).map(|v| v as u16)
    }

    fn u32_at(&self, bytes: &[u8], at: u64) -> Option<u64> {
        self.number_at(bytes, at, 4)
    }

    fn u64_at(&self, bytes: &[u8], at: u64) -> Option<u64> {
        self.number_at(bytes, at, 8)
    }

    /// Bytes of an IFD's entry count, of one entry, and of the next-IFD pointer.
    fn sizes(&self) -> (u64, u64, usize) {
        if self.big {
            (8, 20, 8)
        } else {
            (2, 12, 4)
        }
    }

    /// The entry count of the IFD at `ifd` and the offset of its first entry, when the whole IFD
    /// (entries and next pointer) lies inside the file. A BigTIFF IFD may declare more entries
    /// than the 65 535 a classic one can; as there are no more tags than that, such an IFD is
    /// refused, which bounds the work of reading one page's directory.
    fn entries(&self, bytes: &[u8], ifd: u64) -> Option<(u64, u64)> {
        let (count_size, entry_size, pointer_size) = self.sizes();
        let count = self
            .number_at(bytes, ifd, count_size as usize)
            .filter(|&count| count <= u64::from(u16::MAX))?;
        let first = ifd.checked_add(count_size)?;
        let end = count
            .checked_mul(entry_size)?
            .checked_add(first)?
            .checked_add(pointer_size as u64)?;
        (end <= bytes.len() as u64).then_some((count, first))
    }

    /// The next IFD after the valid IFD at `ifd`: `Ok(None)` at the end of the chain (a zero
    /// pointer), `Err(())` when the pointer leads outside the file or to a truncated IFD.
    fn next(&self, bytes: &[u8], ifd: u64) -> Result<Option<u64>, ()> {
        let (count, first) = self.entries(bytes, ifd).ok_or(())?;
        let (_, entry_size, pointer_size) = self.sizes();
        let at = first + count * entry_size;
        let next = self.number_at(bytes, at, pointer_size).ok_or(())?;
        if next == 0 {
            return Ok(None);
        }
        self.entries(bytes, next).map(|_| Some(next)).ok_or(())
    }
}

/// Walks the IFD chain of a TIFF file, keeping the offsets of at most `max_pages` pages. `None`
/// when `bytes` are not a TIFF file or its first IFD is unreadable (the codec then says why).
pub(crate) fn chain(bytes: &[u8], max_pages: u64) -> Option<Chain> {
    let header = Header::read(bytes)?;
    header.entries(bytes, header.first)?;
    // Both pointers of Floyd's test step through valid IFDs only; a bad pointer ends the chain.
    let step = |ifd: u64| header.next(bytes, ifd).ok().flatten();
    let (count, cycle) = chain_length(header.first, step);
    let mut damaged = cycle;
    let mut pages = Vec::new();
    let mut ifd = Some(header.first);
    while let Some(at) = ifd {
        if pages.len() as u64 >= count.min(max_pages) {
            break;
        }
        pages.push(at);
        ifd = match header.next(bytes, at) {
            Ok(next) => next,
            Err(()) => {
                damaged = true;
                None
            }
        };
    }
    Some(Chain {
        header,
        pages,
        count,
        damaged,
    })
}

/// The number of distinct nodes reachable from `first` by `next`, and whether the walk returns to
/// one of them (Floyd's tortoise and hare: constant memory, at most about three steps per node).
fn chain_length(first: u64, next: impl Fn(u64) -> Option<u64>) -> (u64, bool) {
    let (mut slow, mut fast, mut reached) = (first, first, 1u64);
    loop {
        for _ in 0..2 {
            match next(fast) {
                Some(node) => {
                    fast = node;
                    reached += 1;
                }
                None => return (reached, false),
            }
        }
        let Some(node) = next(slow) else {
            return (reached, false);
        };
        slow = node;
        if slow == fast {
            break;
        }
    }
    // A cycle: the first repeated node is `mu` steps from the start, the loop `lambda` long.
    let (mut slow, mut mu) = (first, 0u64);
    while slow != fast {
        match (next(slow), next(fast)) {
            (Some(a), Some(b)) => (slow, fast) = (a, b),
            _ => return (mu, true),
        }
        mu += 1;
    }
    let mut lambda = 1u64;
    let mut probe = next(slow);
    while let Some(node) = probe.filter(|&node| node != slow) {
        probe = next(node);
        lambda += 1;
    }
    (mu + lambda, true)
}

/// How to read one page: the byte edits that make it readable as the file's first and only page,
/// and what to do to its decoded pixels.
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub(crate) struct PageFix {
    pub(crate) patches: Vec<Patch>,
    /// A JPEG-compressed page in YCbCr: shown to the codec as RGB (which it reads), its decoded
    /// samples are YCbCr still and must be converted.
    pub(crate) ycbcr: bool,
}

/// The edits for the page at `ifd`: the header's first-IFD pointer; a Predictor tag the page's
/// compression does not define set to 1 (none); a JPEG page's YCbCr photometric interpretation
/// shown as RGB. `Err` names a predictor value that TIFF does not define, on a compression that
/// uses it.
pub(crate) fn page_fix(bytes: &[u8], header: &Header, ifd: u64) -> Result<PageFix, String> {
    let mut fix = PageFix::default();
    if ifd != header.first {
        let (at, size) = if header.big { (8, 8) } else { (4, 4) };
        fix.patches.push(Patch::number(header, at, ifd, size));
    }
    let Some((count, first)) = header.entries(bytes, ifd) else {
        return Ok(fix);
    };
    let (_, entry_size, _) = header.sizes();
    // The compression defaults to 1 (none), the samples per pixel to 1.
    let (mut compression, mut samples) = (1, 1);
    let (mut predictor, mut photometric) = (None, None);
    for i in 0..count {
        let entry = first + i * entry_size;
        let Some(tag) = header.u16_at(bytes, entry) else {
            break;
        };
        let value = || inline_value(bytes, header, entry);
        match tag {
            TAG_COMPRESSION => compression = value().unwrap_or(compression),
            TAG_SAMPLES_PER_PIXEL => samples = value().unwrap_or(samples),
            TAG_PREDICTOR => predictor = Some((entry, value())),
            TAG_PHOTOMETRIC => photometric = Some((entry, value())),
            _ => {}
        }
    }
    if let Some((entry, value)) = predictor {
        if PREDICTED_COMPRESSIONS.contains(&compression) {
            match value {
                Some(1..=3) => {}
                Some(value) => {
                    return Err(format!(
                        "the TIFF page's predictor (tag 317) is {value}, which TIFF does not \
                         define (1 none, 2 horizontal differencing, 3 floating point)"
                    ))
                }
                None => return Err("the TIFF page's predictor (tag 317) is not one number".into()),
            }
        } else {
            fix.patches.push(Patch::short_entry(header, entry, 1));
        }
    }
    if let Some((entry, Some(PHOTOMETRIC_YCBCR))) = photometric {
        if compression == COMPRESSION_JPEG && samples == 3 {
            fix.patches
                .push(Patch::short_entry(header, entry, PHOTOMETRIC_RGB));
            fix.ycbcr = true;
        }
    }
    fix.patches.sort_by_key(|p| p.at);
    Ok(fix)
}

/// The value of a one-number SHORT, LONG or LONG8 entry stored in the entry itself.
fn inline_value(bytes: &[u8], header: &Header, entry: u64) -> Option<u64> {
    let field_type = header.u16_at(bytes, entry + 2)?;
    let (count, value_at) = if header.big {
        (header.u64_at(bytes, entry + 4)?, entry + 12)
    } else {
        (header.u32_at(bytes, entry + 4)?, entry + 8)
    };
    if count != 1 {
        return None;
    }
    match field_type {
        3 => header.number_at(bytes, value_at, 2),
        4 => header.number_at(bytes, value_at, 4),
        16 if header.big => header.number_at(bytes, value_at, 8),
        _ => None,
    }
}

impl Header {
    /// `value` as `size` bytes in the file's byte order.
    fn encode(&self, value: u64, size: usize) -> Vec<u8> {
        let big_endian = value.to_be_bytes();
        let bytes = &big_endian[8 - size..];
        if self.little_endian {
            bytes.iter().rev().copied().collect()
        } else {
            bytes.to_vec()
        }
    }
}

/// Bytes shown instead of the file's at one place.
#[derive(Clone, Debug, PartialEq, Eq)]
pub(crate) struct Patch {
    at: u64,
    bytes: Vec<u8>,
}

impl Patch {
    fn number(header: &Header, at: u64, value: u64, size: usize) -> Patch {
        Patch {
            at,
            bytes: header.encode(value, size),
        }
    }

    /// The directory entry at `entry` made a SHORT holding `value`: type, count 1 and value, in
    /// the field after the tag.
    fn short_entry(header: &Header, entry: u64, value: u64) -> Patch {
        let (count_size, value_size) = if header.big { (8, 8) } else { (4, 4) };
        let mut field = header.encode(u64::from(TYPE_SHORT), 2);
        field.extend(header.encode(1, count_size));
        field.extend(header.encode(value, 2));
        field.resize(2 + count_size + value_size, 0);
        Patch {
            at: entry + 2,
            bytes: field,
        }
    }
}

/// A reader over `bytes` as if `patches` (sorted, disjoint, inside the file) were written over
/// them.
pub(crate) struct PatchedReader<'a> {
    bytes: &'a [u8],
    patches: Vec<Patch>,
    position: u64,
}

impl<'a> PatchedReader<'a> {
    pub(crate) fn new(bytes: &'a [u8], patches: Vec<Patch>) -> Self {
        PatchedReader {
            bytes,
            patches,
            position: 0,
        }
    }
}

impl BufRead for PatchedReader<'_> {
    fn fill_buf(&mut self) -> io::Result<&[u8]> {
        let len = self.bytes.len() as u64;
        if self.position >= len {
            return Ok(&[]);
        }
        let mut end = len;
        for patch in &self.patches {
            let patch_end = patch.at + patch.bytes.len() as u64;
            if patch.at <= self.position && self.position < patch_end {
                return Ok(&patch.bytes[(self.position - patch.at) as usize..]);
            }
            if patch.at > self.position {
                end = end.min(patch.at);
                break;
            }
        }
        Ok(&self.bytes[self.position as usize..end as usize])
    }

    fn consume(&mut self, amount: usize) {
        self.position = self.position.saturating_add(amount as u64);
    }
}

impl Read for PatchedReader<'_> {
    fn read(&mut self, out: &mut [u8]) -> io::Result<usize> {
        let available = self.fill_buf()?;
        let n = available.len().min(out.len());
        out[..n].copy_from_slice(&available[..n]);
        self.consume(n);
        Ok(n)
    }
}

impl Seek for PatchedReader<'_> {
    fn seek(&mut self, to: SeekFrom) -> io::Result<u64> {
        let target = match to {
            SeekFrom::Start(at) => Some(at),
            SeekFrom::End(delta) => (self.bytes.len() as u64).checked_add_signed(delta),
            SeekFrom::Current(delta) => self.position.checked_add_signed(delta),
        };
        match target {
            Some(at) => {
                self.position = at;
                Ok(at)
            }
            None => Err(io::Error::new(
                io::ErrorKind::InvalidInput,
                "seek before the start of the file",
            )),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn chain_length_counts_distinct_nodes_and_finds_cycles() {
        let line = |n: u64| move |x: u64| (x + 1 < n).then_some(x + 1);
        assert_eq!(chain_length(0, line(1)), (1, false));
        assert_eq!(chain_length(0, line(2)), (2, false));
        assert_eq!(chain_length(0, line(7)), (7, false));
        // 0 -> 1 -> 2 -> 3 -> 4 -> 2: five distinct nodes.
        let rho = |x: u64| Some(if x == 4 { 2 } else { x + 1 });
        assert_eq!(chain_length(0, rho), (5, true));
        // A node pointing at itself.
        assert_eq!(chain_length(9, |_| Some(9)), (1, true));
        let two = |x: u64| Some(1 - x);
        assert_eq!(chain_length(0, two), (2, true));
    }

    #[test]
    fn a_bigtiff_directory_of_more_entries_than_tags_is_refused() {
        let entries = 70_000u64;
        let mut bytes = b"II\x2b\x00\x08\x00\x00\x00".to_vec();
        bytes.extend_from_slice(&16u64.to_le_bytes());
        bytes.extend_from_slice(&entries.to_le_bytes());
        bytes.resize(bytes.len() + 20 * entries as usize + 8, 0);
        let header = Header::read(&bytes).expect("a BigTIFF header");
        assert!(header.big);
        assert_eq!(header.entries(&bytes, 16), None);
        assert_eq!(chain(&bytes, 10), None);
        // 65 535 entries are read.
        bytes[16..24].copy_from_slice(&65_535u64.to_le_bytes());
        assert_eq!(header.entries(&bytes, 16), Some((65_535, 24)));
        assert_eq!(chain(&bytes, 10).map(|c| c.count), Some(1));
    }

    #[test]
    fn the_patched_reader_shows_the_patches() {
        let bytes: Vec<u8> = (0..20).collect();
        let patches = vec![
            Patch {
                at: 4,
                bytes: vec![100, 101],
            },
            Patch {
                at: 10,
                bytes: vec![200],
            },
        ];
        let mut reader = PatchedReader::new(&bytes, patches);
        let mut all = Vec::new();
        reader.read_to_end(&mut all).expect("read");
        let mut expected = bytes.clone();
        expected[4] = 100;
        expected[5] = 101;
        expected[10] = 200;
        assert_eq!(all, expected);
        reader.seek(SeekFrom::Start(5)).expect("seek");
        let mut three = [0; 3];
        reader.read_exact(&mut three).expect("read");
        assert_eq!(three, [101, 6, 7]);
        assert_eq!(reader.seek(SeekFrom::End(-1)).expect("seek"), 19);
        assert!(reader.seek(SeekFrom::Current(-100)).is_err());
    }
}
