//! Size bounds on the variable-length fields of the axis-state messages, checked while decoding
//! (serde, as ros2-client decodes DDS samples, and [`crate::cdr`] for recordings), so a hostile or
//! broken publisher's JointState with a million joints or a megabyte frame id is refused at its
//! count, before anything is allocated for it.

use serde::de::{Deserializer, Error, SeqAccess, Visitor};

/// Most joints (names, positions, velocities, efforts) in one state message: a machine tool has
/// five to a dozen, a cell of robots a few dozen.
pub const MAX_JOINTS: usize = 256;
/// Longest joint name, bytes.
pub const MAX_NAME_BYTES: usize = 256;
/// Longest `header.frame_id`, bytes.
pub const MAX_FRAME_ID_BYTES: usize = 1024;

struct Bounded<T> {
    max: usize,
    what: &'static str,
    _t: std::marker::PhantomData<T>,
}

impl<'de, T: serde::Deserialize<'de>> Visitor<'de> for Bounded<T> {
    type Value = Vec<T>;
    fn expecting(&self, f: &mut std::fmt::Formatter) -> std::fmt::Result {
        write!(f, "a sequence of at most {} {}", self.max, self.what)
    }
    fn visit_seq<A: SeqAccess<'de>>(self, mut a: A) -> Result<Vec<T>, A::Error> {
        if let Some(n) = a.size_hint().filter(|&n| n > self.max) {
            return Err(A::Error::custom(format!("{n} {}: more than {}", self.what, self.max)));
        }
        let mut out = Vec::with_capacity(a.size_hint().unwrap_or(0).min(self.max));
        while let Some(x) = a.next_element()? {
            if out.len() == self.max {
                return Err(A::Error::custom(format!("more than {} {}", self.max, self.what)));
            }
            out.push(x);
        }
        Ok(out)
    }
}

/// A sequence of at most `max` elements, refused at its count where the format gives one.
fn seq<'de, D: Deserializer<'de>, T: serde::Deserialize<'de>>(d: D, max: usize, what: &'static str) -> Result<Vec<T>, D::Error> {
    d.deserialize_seq(Bounded { max, what, _t: std::marker::PhantomData })
}

/// A string of at most `max` bytes.
struct BoundedStr {
    max: usize,
    what: &'static str,
}

impl BoundedStr {
    fn check<E: Error>(&self, len: usize) -> Result<(), E> {
        if len > self.max {
            return Err(E::custom(format!("{} of {len} bytes: more than {}", self.what, self.max)));
        }
        Ok(())
    }
}

impl<'de> Visitor<'de> for BoundedStr {
    type Value = String;
    fn expecting(&self, f: &mut std::fmt::Formatter) -> std::fmt::Result {
        write!(f, "a {} of at most {} bytes", self.what, self.max)
    }
    // Judged before copying: a borrowed string over the bound is never allocated.
    fn visit_str<E: Error>(self, v: &str) -> Result<String, E> {
        self.check(v.len()).map(|()| v.to_owned())
    }
    fn visit_string<E: Error>(self, v: String) -> Result<String, E> {
        self.check(v.len()).map(|()| v)
    }
}

/// One joint name (a sequence element).
struct Name(String);

impl<'de> serde::Deserialize<'de> for Name {
    fn deserialize<D: Deserializer<'de>>(d: D) -> Result<Name, D::Error> {
        d.deserialize_string(BoundedStr { max: MAX_NAME_BYTES, what: "joint name" }).map(Name)
    }
}

/// `name` of a state message: at most [`MAX_JOINTS`] names of at most [`MAX_NAME_BYTES`] each.
pub fn names<'de, D: Deserializer<'de>>(d: D) -> Result<Vec<String>, D::Error> {
    Ok(seq::<D, Name>(d, MAX_JOINTS, "joint names")?.into_iter().map(|n| n.0).collect())
}

/// `position`, `velocity`, `acceleration`, `effort`: at most [`MAX_JOINTS`] values.
pub fn values<'de, D: Deserializer<'de>>(d: D) -> Result<Vec<f64>, D::Error> {
    seq(d, MAX_JOINTS, "joint values")
}

/// `header.frame_id`: at most [`MAX_FRAME_ID_BYTES`].
pub fn frame_id<'de, D: Deserializer<'de>>(d: D) -> Result<String, D::Error> {
    d.deserialize_string(BoundedStr { max: MAX_FRAME_ID_BYTES, what: "frame_id" })
}
