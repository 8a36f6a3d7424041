//! Finds non-finite numbers in anything serialisable, with their key path.
//!
//! `serde_json` silently writes NaN and infinities as `null`, which would turn a
//! bug upstream into a plausible-looking `summary.json`. Walking the value with
//! this serializer first lets the writer refuse it and say which key is at fault.

use serde::ser::{self, Serialize};
use std::fmt;

/// The key path (e.g. `coordination.mean_bulk`) of the first non-finite float in
/// `value`, or `None` if every float in it is finite.
pub fn first_non_finite<T: Serialize + ?Sized>(value: &T) -> Option<String> {
    let mut finder = Finder { path: Vec::new() };
    match value.serialize(&mut finder) {
        Err(Stop::Found(path)) => Some(path),
        // Other failures are the real serializer's to report.
        Ok(()) | Err(Stop::Other(_)) => None,
    }
}

struct Finder {
    path: Vec<String>,
}

#[derive(Debug)]
enum Stop {
    Found(String),
    Other(String),
}

impl fmt::Display for Stop {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Stop::Found(p) => write!(f, "non-finite number at {p}"),
            Stop::Other(m) => f.write_str(m),
        }
    }
}

impl std::error::Error for Stop {}

impl ser::Error for Stop {
    fn custom<T: fmt::Display>(msg: T) -> Self {
        Stop::Other(msg.to_string())
    }
}

impl Finder {
    fn float(&self, v: f64) -> Result<(), Stop> {
        if v.is_finite() {
            Ok(())
        } else {
            let path = self.path.concat();
            Err(Stop::Found(path.trim_start_matches('.').to_string()))
        }
    }

    fn nested<T: Serialize + ?Sized>(&mut self, segment: String, v: &T) -> Result<(), Stop> {
        self.path.push(segment);
        let r = v.serialize(&mut *self);
        self.path.pop();
        r
    }
}

/// The text of a map key, for the path.
fn key_text<T: Serialize + ?Sized>(key: &T) -> String {
    match serde_json::to_value(key) {
        Ok(serde_json::Value::String(s)) => s,
        Ok(v) => v.to_string(),
        Err(_) => "?".into(),
    }
}

/// Sequences and maps: `index` counts elements, `key` holds the pending map key.
struct Compound<'a> {
    finder: &'a mut Finder,
    index: usize,
    key: String,
}

impl Compound<'_> {
    fn element<T: Serialize + ?Sized>(&mut self, v: &T) -> Result<(), Stop> {
        let seg = format!("[{}]", self.index);
        self.index += 1;
        self.finder.nested(seg, v)
    }
}

macro_rules! ignore {
    ($($name:ident: $t:ty),*) => {
        $(fn $name(self, _v: $t) -> Result<(), Stop> { Ok(()) })*
    };
}

// Tuples, structs and their variants are walked as sequences: the path needs
// their length, not their names.
macro_rules! as_seq {
    ($($name:ident($($ignored:ty),*)),*) => {
        $(fn $name(self, $(_: $ignored,)* len: usize) -> Result<Self::SerializeSeq, Stop> {
            self.serialize_seq(Some(len))
        })*
    };
}

impl<'a> ser::Serializer for &'a mut Finder {
    type Ok = ();
    type Error = Stop;
    type SerializeSeq = Compound<'a>;
    type SerializeTuple = Compound<'a>;
    type SerializeTupleStruct = Compound<'a>;
    type SerializeTupleVariant = Compound<'a>;
    type SerializeMap = Compound<'a>;
    type SerializeStruct = Compound<'a>;
    type SerializeStructVariant = Compound<'a>;

    ignore!(serialize_bool: bool, serialize_i8: i8, serialize_i16: i16, serialize_i32: i32,
        serialize_i64: i64, serialize_u8: u8, serialize_u16: u16, serialize_u32: u32,
        serialize_u64: u64, serialize_char: char, serialize_str: &str, serialize_bytes: &[u8],
        serialize_unit_struct: &'static str);

    fn serialize_f32(self, v: f32) -> Result<(), Stop> {
        self.float(v as f64)
    }
    fn serialize_f64(self, v: f64) -> Result<(), Stop> {
        self.float(v)
    }
    fn serialize_none(self) -> Result<(), Stop> {
        Ok(())
    }
    fn serialize_some<T: Serialize + ?Sized>(self, v: &T) -> Result<(), Stop> {
        v.serialize(self)
    }
    fn serialize_unit(self) -> Result<(), Stop> {
        Ok(())
    }
    fn serialize_unit_variant(self, _: &'static str, _: u32, _: &'static str) -> Result<(), Stop> {
        Ok(())
    }
    fn serialize_newtype_struct<T: Serialize + ?Sized>(
        self,
        _: &'static str,
        v: &T,
    ) -> Result<(), Stop> {
        v.serialize(self)
    }
    fn serialize_newtype_variant<T: Serialize + ?Sized>(
        self,
        _: &'static str,
        _: u32,
        variant: &'static str,
        v: &T,
    ) -> Result<(), Stop> {
        self.nested(format!(".{variant}"), v)
    }
    fn serialize_seq(self, _: Option<usize>) -> Result<Compound<'a>, Stop> {
        Ok(Compound {
            finder: self,
            index: 0,
            key: String::new(),
        })
    }
    fn serialize_map(self, len: Option<usize>) -> Result<Compound<'a>, Stop> {
        self.serialize_seq(len)
    }
    as_seq!(
        serialize_tuple(),
        serialize_tuple_struct(&'static str),
        serialize_tuple_variant(&'static str, u32, &'static str),
        serialize_struct(&'static str),
        serialize_struct_variant(&'static str, u32, &'static str)
    );
}

// Sequences and tuples number their items; one body serves all four.
macro_rules! elements {
    ($($kind:ident :: $method:ident),*) => {$(
        impl ser::$kind for Compound<'_> {
            type Ok = ();
            type Error = Stop;
            fn $method<T: Serialize + ?Sized>(&mut self, v: &T) -> Result<(), Stop> {
                self.element(v)
            }
            fn end(self) -> Result<(), Stop> {
                Ok(())
            }
        }
    )*};
}

elements!(
    SerializeSeq::serialize_element,
    SerializeTuple::serialize_element,
    SerializeTupleStruct::serialize_field,
    SerializeTupleVariant::serialize_field
);

impl ser::SerializeMap for Compound<'_> {
    type Ok = ();
    type Error = Stop;
    fn serialize_key<T: Serialize + ?Sized>(&mut self, key: &T) -> Result<(), Stop> {
        self.key = key_text(key);
        Ok(())
    }
    fn serialize_value<T: Serialize + ?Sized>(&mut self, v: &T) -> Result<(), Stop> {
        let seg = format!(".{}", self.key);
        self.finder.nested(seg, v)
    }
    fn end(self) -> Result<(), Stop> {
        Ok(())
    }
}

// Structs and struct variants name their fields alike.
macro_rules! fields {
    ($($kind:ident),*) => {$(
        impl ser::$kind for Compound<'_> {
            type Ok = ();
            type Error = Stop;
            fn serialize_field<T: Serialize + ?Sized>(
                &mut self,
                key: &'static str,
                v: &T,
            ) -> Result<(), Stop> {
                self.finder.nested(format!(".{key}"), v)
            }
            fn end(self) -> Result<(), Stop> {
                Ok(())
            }
        }
    )*};
}

fields!(SerializeStruct, SerializeStructVariant);

#[cfg(test)]
mod tests {
    use super::*;
    use serde::Serialize;
    use std::collections::BTreeMap;

    #[derive(Serialize)]
    struct Inner {
        mean: f64,
        list: Vec<f64>,
    }

    #[derive(Serialize)]
    struct Outer {
        name: &'static str,
        inner: Inner,
        #[serde(flatten)]
        extra: BTreeMap<String, f64>,
    }

    fn outer(mean: f64, last: f64, extra: f64) -> Outer {
        Outer {
            name: "x",
            inner: Inner {
                mean,
                list: vec![1.0, last],
            },
            extra: [("bulk".to_string(), extra)].into_iter().collect(),
        }
    }

    #[test]
    fn finite_values_pass() {
        assert_eq!(first_non_finite(&outer(1.0, 2.0, 3.0)), None);
    }

    #[test]
    fn paths_name_the_key() {
        let p = first_non_finite(&outer(f64::NAN, 2.0, 3.0));
        assert_eq!(p.as_deref(), Some("inner.mean"));
        let p = first_non_finite(&outer(1.0, f64::INFINITY, 3.0));
        assert_eq!(p.as_deref(), Some("inner.list[1]"));
        let p = first_non_finite(&outer(1.0, 2.0, f64::NAN));
        assert_eq!(p.as_deref(), Some("bulk"));
    }
}
