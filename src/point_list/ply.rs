//! PLY point files: the `vertex` element's `x`, `y` and `z` (any scalar type), from ASCII,
//! binary little-endian or binary big-endian bodies; other elements and properties are skipped.
//! Every failure is an [`Error::PointFile`] that says what is wrong, never a panic.

use crate::error::{Error, Result};

#[derive(Clone, Copy, Debug, PartialEq)]
enum Scalar {
    I8,
    U8,
    I16,
    U16,
    I32,
    U32,
    F32,
    F64,
}

impl Scalar {
    fn parse(name: &str) -> Option<Scalar> {
        Some(match name {
            "char" | "int8" => Scalar::I8,
            "uchar" | "uint8" => Scalar::U8,
            "short" | "int16" => Scalar::I16,
            "ushort" | "uint16" => Scalar::U16,
            "int" | "int32" => Scalar::I32,
            "uint" | "uint32" => Scalar::U32,
            "float" | "float32" => Scalar::F32,
            "double" | "float64" => Scalar::F64,
            _ => return None,
        })
    }

    fn size(self) -> usize {
        match self {
            Scalar::I8 | Scalar::U8 => 1,
            Scalar::I16 | Scalar::U16 => 2,
            Scalar::I32 | Scalar::U32 | Scalar::F32 => 4,
            Scalar::F64 => 8,
        }
    }

    fn read(self, bytes: &[u8], little: bool) -> f64 {
        macro_rules! num {
            ($t:ty, $n:expr) => {{
                let mut a = [0u8; $n];
                a.copy_from_slice(&bytes[..$n]);
                if little {
                    <$t>::from_le_bytes(a) as f64
                } else {
                    <$t>::from_be_bytes(a) as f64
                }
            }};
        }
        match self {
            Scalar::I8 => bytes[0] as i8 as f64,
            Scalar::U8 => bytes[0] as f64,
            Scalar::I16 => num!(i16, 2),
            Scalar::U16 => num!(u16, 2),
            Scalar::I32 => num!(i32, 4),
            Scalar::U32 => num!(u32, 4),
            Scalar::F32 => num!(f32, 4),
            Scalar::F64 => num!(f64, 8),
        }
    }
}

#[derive(Clone, Debug)]
enum Property {
    Scalar(String, Scalar),
    /// A list: the count's type, the items' type (skipped).
    List(Scalar, Scalar),
}

#[derive(Clone, Debug)]
struct Element {
    name: String,
    count: u64,
    properties: Vec<Property>,
}

#[derive(Clone, Copy, Debug, PartialEq)]
enum Body {
    Ascii,
    Binary { little: bool },
}

fn bad(message: impl Into<String>) -> Error {
    Error::PointFile(format!("PLY: {}", message.into()))
}

/// Whether `bytes` start like a PLY file.
pub(crate) fn is_ply(bytes: &[u8]) -> bool {
    bytes.starts_with(b"ply\n") || bytes.starts_with(b"ply\r\n")
}

/// The `vertex` element's `x y z` of a PLY file, in file order.
pub(crate) fn read(bytes: &[u8]) -> Result<Vec<[f64; 3]>> {
    if !is_ply(bytes) {
        return Err(bad("the file does not start with 'ply'"));
    }
    let end = find(bytes, b"end_header")
        .ok_or_else(|| bad("no 'end_header' line: the header is incomplete"))?;
    let mut body_start = end + b"end_header".len();
    if bytes.get(body_start) == Some(&b'\r') {
        body_start += 1;
    }
    if bytes.get(body_start) == Some(&b'\n') {
        body_start += 1;
    }
    let header = std::str::from_utf8(&bytes[..end]).map_err(|_| bad("the header is not text"))?;
    let mut format = None;
    let mut elements: Vec<Element> = Vec::new();
    for (i, line) in header.lines().enumerate().skip(1) {
        let words: Vec<&str> = line.split_whitespace().collect();
        let at = |what: &str| bad(format!("header line {}: {what}: '{}'", i + 1, line.trim()));
        match words.first().copied() {
            None | Some("comment") | Some("obj_info") => {}
            Some("format") => {
                format = Some(match words.get(1).copied() {
                    Some("ascii") => Body::Ascii,
                    Some("binary_little_endian") => Body::Binary { little: true },
                    Some("binary_big_endian") => Body::Binary { little: false },
                    _ => return Err(at("unknown format")),
                });
            }
            Some("element") => {
                let (Some(name), Some(count)) = (words.get(1), words.get(2)) else {
                    return Err(at("expected 'element <name> <count>'"));
                };
                let count = count
                    .parse::<u64>()
                    .map_err(|_| at("the element count is not a whole number"))?;
                elements.push(Element {
                    name: name.to_string(),
                    count,
                    properties: Vec::new(),
                });
            }
            Some("property") => {
                let element = elements
                    .last_mut()
                    .ok_or_else(|| at("a property before any element"))?;
                let property = match words.get(1).copied() {
                    Some("list") => {
                        let (Some(count), Some(item), Some(_name)) =
                            (words.get(2), words.get(3), words.get(4))
                        else {
                            return Err(at("expected 'property list <count type> <type> <name>'"));
                        };
                        let count = Scalar::parse(count).ok_or_else(|| at("unknown type"))?;
                        let item = Scalar::parse(item).ok_or_else(|| at("unknown type"))?;
                        Property::List(count, item)
                    }
                    Some(kind) => {
                        let name = words
                            .get(2)
                            .ok_or_else(|| at("expected 'property <type> <name>'"))?;
                        let kind = Scalar::parse(kind).ok_or_else(|| at("unknown type"))?;
                        Property::Scalar(name.to_string(), kind)
                    }
                    None => return Err(at("expected 'property <type> <name>'")),
                };
                element.properties.push(property);
            }
            Some(_) => return Err(at("unknown header line")),
        }
    }
    let format = format.ok_or_else(|| bad("no 'format' line in the header"))?;
    let vertex_index = elements
        .iter()
        .position(|e| e.name == "vertex")
        .ok_or_else(|| bad("no 'vertex' element"))?;
    let vertex = &elements[vertex_index];
    let column = |axis: &str| {
        vertex
            .properties
            .iter()
            .position(|p| matches!(p, Property::Scalar(name, _) if name == axis))
            .ok_or_else(|| {
                bad(format!(
                    "the vertex element has no scalar property '{axis}'"
                ))
            })
    };
    let columns = [column("x")?, column("y")?, column("z")?];
    let body = &bytes[body_start..];
    match format {
        Body::Ascii => read_ascii(body, &elements, vertex_index, columns),
        Body::Binary { little } => read_binary(body, &elements, vertex_index, columns, little),
    }
}

fn find(haystack: &[u8], needle: &[u8]) -> Option<usize> {
    haystack.windows(needle.len()).position(|w| w == needle)
}

fn read_ascii(
    body: &[u8],
    elements: &[Element],
    vertex_index: usize,
    columns: [usize; 3],
) -> Result<Vec<[f64; 3]>> {
    let text = std::str::from_utf8(body).map_err(|_| bad("the ASCII body is not text"))?;
    let mut lines = text.lines().filter(|l| !l.trim().is_empty());
    // Elements before the vertices: one line per item.
    for element in &elements[..vertex_index] {
        for _ in 0..element.count {
            lines.next().ok_or_else(|| {
                bad(format!(
                    "the body ends inside the '{}' element",
                    element.name
                ))
            })?;
        }
    }
    let vertex = &elements[vertex_index];
    let mut out = Vec::with_capacity((vertex.count as usize).min(body.len() / 6 + 1));
    for v in 0..vertex.count {
        let line = lines.next().ok_or_else(|| {
            bad(format!(
                "the header announces {} vertices, the body holds {v}",
                vertex.count
            ))
        })?;
        let values: Vec<&str> = line.split_whitespace().collect();
        let mut point = [0.0; 3];
        for (k, &c) in columns.iter().enumerate() {
            let word = values.get(c).ok_or_else(|| {
                bad(format!(
                    "vertex {}: {} values, fewer than its properties",
                    v + 1,
                    values.len()
                ))
            })?;
            let value = word
                .parse::<f64>()
                .map_err(|_| bad(format!("vertex {}: '{word}' is not a number", v + 1)))?;
            if !value.is_finite() {
                return Err(bad(format!("vertex {}: '{word}' is not finite", v + 1)));
            }
            point[k] = value;
        }
        out.push(point);
    }
    Ok(out)
}

fn read_binary(
    body: &[u8],
    elements: &[Element],
    vertex_index: usize,
    columns: [usize; 3],
    little: bool,
) -> Result<Vec<[f64; 3]>> {
    let short = |name: &str| bad(format!("the binary body ends inside the '{name}' element"));
    let mut at = 0usize;
    let take = |at: &mut usize, size: usize, name: &str| -> Result<usize> {
        let start = *at;
        if body.len().saturating_sub(start) < size {
            return Err(short(name));
        }
        *at += size;
        Ok(start)
    };
    for element in &elements[..vertex_index] {
        for _ in 0..element.count {
            for property in &element.properties {
                match *property {
                    Property::Scalar(_, kind) => {
                        take(&mut at, kind.size(), &element.name)?;
                    }
                    Property::List(count, item) => {
                        let start = take(&mut at, count.size(), &element.name)?;
                        let n = count.read(&body[start..], little);
                        if !(0.0..1e12).contains(&n) {
                            return Err(bad(format!("a list of {n} items in '{}'", element.name)));
                        }
                        take(&mut at, n as usize * item.size(), &element.name)?;
                    }
                }
            }
        }
    }
    let vertex = &elements[vertex_index];
    // Refuse a count the body cannot hold before allocating for it.
    let row_min: usize = vertex
        .properties
        .iter()
        .map(|p| match p {
            Property::Scalar(_, kind) => kind.size(),
            Property::List(count, _) => count.size(),
        })
        .sum();
    if (vertex.count as u128) * (row_min as u128) > body.len().saturating_sub(at) as u128 {
        return Err(bad(format!(
            "the header announces {} vertices, more than the body holds",
            vertex.count
        )));
    }
    let mut out = Vec::with_capacity(vertex.count as usize);
    let mut row = vec![0.0f64; vertex.properties.len()];
    for v in 0..vertex.count {
        for (slot, property) in row.iter_mut().zip(&vertex.properties) {
            match *property {
                Property::Scalar(_, kind) => {
                    let start = take(&mut at, kind.size(), "vertex")?;
                    *slot = kind.read(&body[start..], little);
                }
                Property::List(count, item) => {
                    let start = take(&mut at, count.size(), "vertex")?;
                    let n = count.read(&body[start..], little);
                    if !(0.0..1e12).contains(&n) {
                        return Err(bad(format!("vertex {}: a list of {n} items", v + 1)));
                    }
                    take(&mut at, n as usize * item.size(), "vertex")?;
                }
            }
        }
        let point = [row[columns[0]], row[columns[1]], row[columns[2]]];
        if !point.iter().all(|c| c.is_finite()) {
            return Err(bad(format!("vertex {} is not finite: {point:?}", v + 1)));
        }
        out.push(point);
    }
    Ok(out)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn header(format: &str, count: usize) -> String {
        format!(
            "ply\nformat {format} 1.0\ncomment made by a test\nelement vertex {count}\n\
             property float x\nproperty float y\nproperty double z\nproperty uchar red\n\
             element face 1\nproperty list uchar int vertex_indices\nend_header\n"
        )
    }

    #[test]
    fn ascii_and_both_binaries_give_the_same_points() {
        let points = [[1.5f32, -2.0, 3.25], [0.0, 4.0, -1.0]];
        let mut ascii = header("ascii", 2).into_bytes();
        for p in points {
            ascii.extend(format!("{} {} {} 200\n", p[0], p[1], p[2]).bytes());
        }
        ascii.extend(b"3 0 1 0\n");
        let mut little = header("binary_little_endian", 2).into_bytes();
        let mut big = header("binary_big_endian", 2).into_bytes();
        for p in points {
            little.extend(p[0].to_le_bytes());
            little.extend(p[1].to_le_bytes());
            little.extend((p[2] as f64).to_le_bytes());
            little.push(7);
            big.extend(p[0].to_be_bytes());
            big.extend(p[1].to_be_bytes());
            big.extend((p[2] as f64).to_be_bytes());
            big.push(7);
        }
        let want = vec![[1.5, -2.0, 3.25], [0.0, 4.0, -1.0]];
        assert_eq!(read(&ascii).unwrap(), want);
        assert_eq!(read(&little).unwrap(), want);
        assert_eq!(read(&big).unwrap(), want);
    }

    #[test]
    fn damaged_files_are_clear_errors() {
        let message = |bytes: &[u8]| match read(bytes) {
            Err(Error::PointFile(m)) => m,
            other => panic!("expected an error, got {other:?}"),
        };
        assert!(message(b"ply\nformat ascii 1.0\n").contains("end_header"));
        assert!(message(b"ply\nformat ascii 1.0\nelement face 0\nend_header\n").contains("vertex"));
        let no_z = b"ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\nproperty float y\nend_header\n1 2\n";
        assert!(message(no_z).contains("'z'"));
        let mut truncated = header("binary_little_endian", 1000).into_bytes();
        truncated.extend([0u8; 13]);
        assert!(message(&truncated).contains("more than the body holds"));
        let mut short = header("ascii", 3).into_bytes();
        short.extend(b"1 2 3 0\n");
        assert!(message(&short).contains("announces 3"));
        let mut nan = header("ascii", 1).into_bytes();
        nan.extend(b"1 nan 3 0\n");
        assert!(message(&nan).contains("not finite"));
        assert!(message(b"ply\nformat weird 1.0\nend_header\n").contains("unknown format"));
        // Any prefix of a good file is an error or a shorter list, never a panic.
        let mut good = header("binary_little_endian", 2).into_bytes();
        good.extend([0u8; 2 * 17 + 1 + 4]);
        for cut in 0..good.len() {
            let _ = read(&good[..cut]);
        }
    }
}
