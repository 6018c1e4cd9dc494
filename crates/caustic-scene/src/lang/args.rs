//! One line split into a command and its arguments, with typed accessors whose errors name
//! the argument, what was expected and the column where it is.

use glam::DVec3;

/// An error within one line: the column it points at and the message.
#[derive(Debug)]
pub(crate) struct Fault {
    pub column: usize,
    pub message: String,
}

pub(crate) type Res<T> = Result<T, Fault>;

/// The tokens of a line up to its comment: a token starting with `#` starts a comment that
/// runs to the end of the line.
pub(crate) fn tokens(line: &str) -> impl Iterator<Item = &str> {
    line.split_whitespace().take_while(|t| !t.starts_with('#'))
}

/// A command line: the command's name and its arguments.
pub(crate) struct Args<'a> {
    line: &'a str,
    /// The command as written.
    pub name: &'a str,
    args: Vec<&'a str>,
    /// The argument synopsis of the command (`x y z radius`), for messages.
    usage: &'static str,
}

/// At most 40 characters of `text`, with control characters escaped, for messages.
pub(crate) fn shown(text: &str) -> String {
    let mut out: String = text.chars().take(40).flat_map(char::escape_debug).collect();
    if text.chars().nth(40).is_some() {
        out.push_str("...");
    }
    out
}

impl<'a> Args<'a> {
    /// Splits `line`; `None` for a blank or comment line.
    pub fn split(line: &'a str) -> Option<(&'a str, Vec<&'a str>)> {
        let mut parts = tokens(line);
        let name = parts.next()?;
        Some((name, parts.collect()))
    }

    pub fn new(line: &'a str, name: &'a str, args: Vec<&'a str>, usage: &'static str) -> Args<'a> {
        Args { line, name, args, usage }
    }

    /// Number of arguments.
    pub fn len(&self) -> usize {
        self.args.len()
    }

    /// One-based column of a token of this line.
    fn column_of(&self, token: &str) -> usize {
        let offset = (token.as_ptr() as usize).saturating_sub(self.line.as_ptr() as usize).min(self.line.len());
        self.line.get(..offset).map_or(offset, |prefix| prefix.chars().count()) + 1
    }

    /// Column of the command's name.
    pub fn name_column(&self) -> usize {
        self.column_of(self.name)
    }

    /// Column of argument `i` (the column just past the last token when it is missing).
    pub fn column(&self, i: usize) -> usize {
        match self.args.get(i) {
            Some(token) => self.column_of(token),
            None => {
                let last = self.args.last().copied().unwrap_or(self.name);
                self.column_of(last) + last.chars().count()
            }
        }
    }

    /// An error at the command's name.
    pub fn fail<T>(&self, message: impl std::fmt::Display) -> Res<T> {
        Err(Fault { column: self.column_of(self.name), message: format!("{}: {message}", self.name) })
    }

    /// An error at argument `i`.
    pub fn fail_at<T>(&self, i: usize, message: impl std::fmt::Display) -> Res<T> {
        Err(Fault { column: self.column(i), message: format!("{}: {message}", self.name) })
    }

    /// The name of argument `i` from the synopsis.
    pub fn arg_name(&self, i: usize) -> String {
        match self.usage.split_whitespace().filter(|w| !w.starts_with('[')).nth(i) {
            Some(name) => name.to_string(),
            None => format!("argument {}", i + 1),
        }
    }

    /// Checks that the number of arguments is one of `counts`.
    pub fn expect(&self, counts: &[usize]) -> Res<()> {
        let n = self.args.len();
        if counts.contains(&n) {
            return Ok(());
        }
        let wanted = match counts {
            [] | [0] => "no arguments".to_string(),
            [1] => "1 argument".to_string(),
            [one] => format!("{one} arguments"),
            [init @ .., last] => format!("{} or {last} arguments", init.iter().map(usize::to_string).collect::<Vec<_>>().join(", ")),
        };
        let synopsis = if self.usage.is_empty() { String::new() } else { format!(" ({} {})", self.name, self.usage) };
        // Too many: point at the first extra argument; too few: just past the last one.
        let most = counts.iter().copied().max().unwrap_or(0);
        let at = if n > most { most } else { n };
        self.fail_at(at, format!("expected {wanted}{synopsis}, found {n}"))
    }

    /// Argument `i` as written.
    pub fn text(&self, i: usize) -> Res<&'a str> {
        match self.args.get(i) {
            Some(text) => Ok(text),
            None => self.fail_at(i, format!("missing {}", self.arg_name(i))),
        }
    }

    /// Argument `i` as a finite number within the range of `f32`.
    pub fn num(&self, i: usize) -> Res<f64> {
        let text = self.text(i)?;
        match text.parse::<f64>() {
            Ok(value) if value.is_finite() && value.abs() <= f64::from(f32::MAX) => Ok(value),
            Ok(_) => self.fail_at(i, format!("{} must be a finite number within the range of f32, found '{}'", self.arg_name(i), shown(text))),
            Err(_) => self.fail_at(i, format!("expected a number for {}, found '{}'", self.arg_name(i), shown(text))),
        }
    }

    /// Argument `i` as an `f32` (parsed as `f64`, then rounded once).
    pub fn f32(&self, i: usize) -> Res<f32> {
        Ok(self.num(i)? as f32)
    }

    /// Argument `i` as an `f32` that must satisfy `ok`, described by `range` in the message.
    pub fn f32_in(&self, i: usize, ok: impl Fn(f32) -> bool, range: &str) -> Res<f32> {
        let value = self.f32(i)?;
        if ok(value) { Ok(value) } else { self.fail_at(i, format!("{} must be {range}, found {}", self.arg_name(i), shown(self.text(i)?))) }
    }

    /// Arguments `i..i + 3` as a vector (each component parsed as `f64`).
    pub fn dvec3(&self, i: usize) -> Res<DVec3> {
        Ok(DVec3::new(self.num(i)?, self.num(i + 1)?, self.num(i + 2)?))
    }

    /// Arguments `i..i + 3` as a vector, each component rounded to `f32` first (so the
    /// result is exactly what `f32` parsing would give).
    pub fn dvec3_f32(&self, i: usize) -> Res<DVec3> {
        Ok(DVec3::new(f64::from(self.f32(i)?), f64::from(self.f32(i + 1)?), f64::from(self.f32(i + 2)?)))
    }

    /// Arguments `i..i + 3` as a colour: finite and not negative.
    pub fn color(&self, i: usize) -> Res<glam::Vec3> {
        let mut rgb = [0.0f32; 3];
        for (k, c) in rgb.iter_mut().enumerate() {
            *c = self.f32(i + k)?;
            if *c < 0.0 {
                return self.fail_at(i + k, format!("colour components must be >= 0, found {}", shown(self.text(i + k)?)));
            }
        }
        Ok(glam::Vec3::from(rgb))
    }

    /// Argument `i` as an integer (an integral decimal such as `640.0` is accepted).
    pub fn int(&self, i: usize) -> Res<i64> {
        let text = self.text(i)?;
        if let Ok(value) = text.parse::<i64>() {
            return Ok(value);
        }
        match text.parse::<f64>() {
            Ok(value) if value.is_finite() && value.fract() == 0.0 && value.abs() < 9.0e15 => Ok(value as i64),
            _ => self.fail_at(i, format!("expected an integer for {}, found '{}'", self.arg_name(i), shown(text))),
        }
    }

    /// Argument `i` as an integer in `min..=max`.
    pub fn int_in(&self, i: usize, min: i64, max: i64) -> Res<i64> {
        let value = self.int(i)?;
        if (min..=max).contains(&value) { Ok(value) } else { self.fail_at(i, format!("{} must be between {min} and {max}, found {value}", self.arg_name(i))) }
    }

    /// Argument `i` as one of `choices`; returns its index.
    pub fn keyword(&self, i: usize, choices: &[&str]) -> Res<usize> {
        let text = self.text(i).or_else(|_| self.fail_at(i, format!("expected {}", one_of(choices))))?;
        match choices.iter().position(|c| *c == text) {
            Some(k) => Ok(k),
            None => self.fail_at(i, format!("expected {}, found '{}'", one_of(choices), shown(text))),
        }
    }
}

/// `a`, `a or b`, `a, b or c`.
pub(crate) fn one_of(choices: &[&str]) -> String {
    match choices {
        [] => String::new(),
        [one] => one.to_string(),
        [init @ .., last] => format!("{} or {last}", init.join(", ")),
    }
}
