//! The XML of the VTK files: escaping, inline base64 binary data arrays, array subsets.

use super::arrays::{ArrayValues, BlockArray};
use base64::Engine;
use std::fmt::Write as _;

pub(super) fn xml_escape(s: &str) -> String {
    s.replace('&', "&amp;")
        .replace('"', "&quot;")
        .replace('<', "&lt;")
        .replace('>', "&gt;")
}

/// Inline binary data: base64 of the byte count (UInt64) followed by the bytes, appended to
/// `out`.
pub(super) fn b64_into(out: &mut String, bytes: &[u8]) {
    let mut buf = Vec::with_capacity(8 + bytes.len());
    buf.extend_from_slice(&(bytes.len() as u64).to_le_bytes());
    buf.extend_from_slice(bytes);
    base64::engine::general_purpose::STANDARD.encode_string(buf, out);
}

pub(super) fn data_array(out: &mut String, ty: &str, name: &str, comps: usize, bytes: &[u8]) {
    let _ = write!(
        out,
        "        <DataArray type=\"{ty}\" Name=\"{}\" NumberOfComponents=\"{comps}\" \
         format=\"binary\">\n          ",
        xml_escape(name),
    );
    b64_into(out, bytes);
    out.push_str("\n        </DataArray>\n");
}

pub(super) fn f64_bytes(v: &[f64]) -> Vec<u8> {
    v.iter().flat_map(|x| x.to_le_bytes()).collect()
}

pub(super) fn i32_bytes(v: &[i32]) -> Vec<u8> {
    v.iter().flat_map(|x| x.to_le_bytes()).collect()
}

pub(super) fn i64_bytes(v: &[i64]) -> Vec<u8> {
    v.iter().flat_map(|x| x.to_le_bytes()).collect()
}

pub(super) fn array_subset(out: &mut String, a: &BlockArray, idx: &[usize]) {
    match &a.values {
        ArrayValues::F64 { components, values } => {
            let k = *components;
            let sub: Vec<f64> = idx
                .iter()
                .flat_map(|&i| values[k * i..k * (i + 1)].iter().copied())
                .collect();
            data_array(out, "Float64", &a.name, k, &f64_bytes(&sub));
        }
        ArrayValues::I32(v) => {
            let sub: Vec<i32> = idx.iter().map(|&i| v[i]).collect();
            data_array(out, "Int32", &a.name, 1, &i32_bytes(&sub));
        }
    }
}
