//! Typed, located access to the tables of a TOML scene file, in the manner of pbrt's
//! `ParameterDictionary`: each scene type reads its own keys with defaults and validation,
//! unknown keys are reported, and every error points at the offending text.

use crate::error::{Location, SceneError, SourceFile};
use glam::Vec3;
use penumbra_core::Rgb;
use std::cell::RefCell;
use std::ops::Range;
use std::sync::Arc;
use toml::de::{DeTable, DeValue};
use toml::Spanned;

pub type Result<T> = std::result::Result<T, SceneError>;

/// A TOML table being read; remembers which keys were read.
pub struct Table<'a> {
    file: &'a Arc<SourceFile>,
    table: &'a DeTable<'a>,
    span: Range<usize>,
    used: RefCell<Vec<String>>,
}

/// A located value in a table.
pub struct Value<'a> {
    file: &'a Arc<SourceFile>,
    value: &'a Spanned<DeValue<'a>>,
}

impl<'a> Table<'a> {
    pub fn new(file: &'a Arc<SourceFile>, table: &'a DeTable<'a>, span: Range<usize>) -> Self {
        Table {
            file,
            table,
            span,
            used: RefCell::new(Vec::new()),
        }
    }

    pub fn location(&self) -> Location {
        Location::new(self.file, self.span.clone())
    }

    pub fn error(&self, message: impl Into<String>) -> SceneError {
        SceneError::at(self.location(), message)
    }

    /// The value of `key`, marking the key as read.
    pub fn get(&self, key: &str) -> Option<Value<'a>> {
        self.used.borrow_mut().push(key.to_string());
        self.table.get(key).map(|value| Value { file: self.file, value })
    }

    pub fn require(&self, key: &str) -> Result<Value<'a>> {
        self.get(key).ok_or_else(|| {
            self.error(format!("missing required key `{key}`"))
                .label("in this table")
        })
    }

    pub fn f32_or(&self, key: &str, default: f32) -> Result<f32> {
        self.get(key).map_or(Ok(default), |v| v.f32())
    }

    /// A number that must be positive.
    pub fn positive_or(&self, key: &str, default: f32) -> Result<f32> {
        match self.get(key) {
            Some(v) => v.positive(),
            None => Ok(default),
        }
    }

    pub fn vec3_or(&self, key: &str, default: Vec3) -> Result<Vec3> {
        self.get(key).map_or(Ok(default), |v| v.vec3())
    }

    pub fn rgb_or(&self, key: &str, default: Rgb) -> Result<Rgb> {
        self.get(key).map_or(Ok(default), |v| v.rgb())
    }

    /// A sub-table, if present.
    pub fn table(&self, key: &str) -> Result<Option<Table<'a>>> {
        self.get(key).map(|v| v.table()).transpose()
    }

    /// An array of tables (`[[key]]`), empty if absent.
    pub fn tables(&self, key: &str) -> Result<Vec<Table<'a>>> {
        match self.get(key) {
            None => Ok(Vec::new()),
            Some(v) => v.array()?.into_iter().map(|v| v.table()).collect(),
        }
    }

    /// Fails on the first key that was never read, listing the keys this table accepts.
    pub fn finish(&self) -> Result<()> {
        let used = self.used.borrow();
        for key in self.table.keys() {
            if !used.iter().any(|u| u == key.get_ref().as_ref()) {
                let mut known: Vec<&str> = used.iter().map(String::as_str).collect();
                known.sort();
                known.dedup();
                return Err(SceneError::at(
                    Location::new(self.file, key.span()),
                    format!("unknown key `{}`", key.get_ref()),
                )
                .label("not a key of this table")
                .help(format!("expected one of: {}", known.join(", "))));
            }
        }
        Ok(())
    }
}

impl<'a> Value<'a> {
    pub fn location(&self) -> Location {
        Location::new(self.file, self.value.span())
    }

    pub fn error(&self, message: impl Into<String>) -> SceneError {
        SceneError::at(self.location(), message)
    }

    fn type_error(&self, expected: &str) -> SceneError {
        self.error(format!(
            "expected {expected}, found {}",
            self.value.get_ref().type_str()
        ))
        .label(format!("expected {expected}"))
    }

    pub fn f32(&self) -> Result<f32> {
        let x = match self.value.get_ref() {
            DeValue::Float(f) => f.as_str().replace('_', "").parse::<f64>().ok(),
            DeValue::Integer(i) => i64::from_str_radix(&i.as_str().replace('_', ""), i.radix())
                .ok()
                .map(|i| i as f64),
            _ => return Err(self.type_error("a number")),
        };
        match x.map(|x| x as f32) {
            Some(x) if x.is_finite() => Ok(x),
            _ => Err(self.error("expected a finite number").label("not a finite number")),
        }
    }

    pub fn positive(&self) -> Result<f32> {
        let x = self.f32()?;
        if x > 0.0 {
            Ok(x)
        } else {
            Err(self.error(format!("must be positive, found {x}")).label("must be > 0"))
        }
    }

    /// A whole number in `range`.
    pub fn integer(&self, range: std::ops::RangeInclusive<i64>) -> Result<i64> {
        let DeValue::Integer(i) = self.value.get_ref() else {
            return Err(self.type_error("a whole number"));
        };
        i64::from_str_radix(&i.as_str().replace('_', ""), i.radix())
            .ok()
            .filter(|n| range.contains(n))
            .ok_or_else(|| {
                self.error(format!(
                    "expected a whole number from {} to {}",
                    range.start(),
                    range.end()
                ))
                .label("out of range")
            })
    }

    pub fn u32(&self) -> Result<u32> {
        self.integer(0..=u32::MAX as i64).map(|n| n as u32)
    }

    pub fn bool(&self) -> Result<bool> {
        self.value
            .get_ref()
            .as_bool()
            .ok_or_else(|| self.type_error("true or false"))
    }

    pub fn str(&self) -> Result<&'a str> {
        self.value.get_ref().as_str().ok_or_else(|| self.type_error("a string"))
    }

    pub fn array(&self) -> Result<Vec<Value<'a>>> {
        match self.value.get_ref() {
            DeValue::Array(items) => Ok(items.iter().map(|value| Value { file: self.file, value }).collect()),
            _ => Err(self.type_error("an array")),
        }
    }

    pub fn table(&self) -> Result<Table<'a>> {
        match self.value.get_ref() {
            DeValue::Table(t) => Ok(Table::new(self.file, t, self.value.span())),
            _ => Err(self.type_error("a table")),
        }
    }

    pub fn is_table(&self) -> bool {
        matches!(self.value.get_ref(), DeValue::Table(_))
    }

    pub fn is_number(&self) -> bool {
        matches!(self.value.get_ref(), DeValue::Float(_) | DeValue::Integer(_))
    }

    /// An array of exactly `n` numbers.
    pub fn numbers(&self, n: usize) -> Result<Vec<f32>> {
        let items = self
            .array()
            .map_err(|_| self.type_error(&format!("an array of {n} numbers")))?;
        if items.len() != n {
            return Err(self
                .error(format!("expected {n} numbers, found {}", items.len()))
                .label(format!("expected {n} numbers")));
        }
        items.iter().map(Value::f32).collect()
    }

    pub fn vec3(&self) -> Result<Vec3> {
        self.numbers(3).map(|v| Vec3::new(v[0], v[1], v[2]))
    }

    /// A colour: `[r, g, b]` or a single number for grey. Negative values are rejected.
    pub fn rgb(&self) -> Result<Rgb> {
        let c = if self.is_number() {
            Rgb::splat(self.f32()?)
        } else {
            Rgb::from(self.vec3()?.to_array())
        };
        if c.r < 0.0 || c.g < 0.0 || c.b < 0.0 {
            return Err(self
                .error("colour components must not be negative")
                .label("negative component"));
        }
        Ok(c)
    }
}

/// Parses TOML text into its root table, or a located syntax error.
pub fn parse_toml(file: &Arc<SourceFile>) -> Result<Spanned<DeTable<'_>>> {
    DeTable::parse(&file.text).map_err(|e| {
        let span = e.span().unwrap_or(0..0);
        SceneError::at(Location::new(file, span), format!("TOML syntax error: {}", e.message())).label("syntax error")
    })
}
