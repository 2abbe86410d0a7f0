//! The arguments of an element class, bound by the element's signature
//! (`Definition::SIGNATURE`): the dofs first (indices, dof labels, None for the ground),
//! physical parameters keyword-only. Old spellings (positional physical parameters, renamed
//! parameters) are mapped onto the new names with a `DeprecationWarning` naming them.

use pyo3::exceptions::{PyDeprecationWarning, PyTypeError};
use pyo3::prelude::*;
use pyo3::types::{PyDict, PyTuple};

/// One parameter of a signature.
pub(crate) struct Param {
    pub name: String,
    pub keyword_only: bool,
    pub required: bool,
}

/// A parsed signature, e.g. `(i, j=None, *, k, fy, alpha=0.0)`.
pub(crate) struct Signature {
    pub text: &'static str,
    pub params: Vec<Param>,
}

impl Signature {
    /// Parses `text` (names, `=default`, a bare `*` before the keyword-only ones).
    pub(crate) fn parse(text: &'static str) -> Self {
        let inner = text.trim().trim_start_matches('(').trim_end_matches(')');
        let mut keyword_only = false;
        let mut params = Vec::new();
        for part in split_top(inner) {
            let part = part.trim();
            if part.is_empty() {
                continue;
            }
            if part == "*" {
                keyword_only = true;
                continue;
            }
            let (name, required) = match part.split_once('=') {
                Some((n, _)) => (n.trim(), false),
                None => (part, true),
            };
            params.push(Param {
                name: name.to_owned(),
                keyword_only,
                required,
            });
        }
        Signature { text, params }
    }

    fn positional(&self) -> impl Iterator<Item = &Param> {
        self.params.iter().filter(|p| !p.keyword_only)
    }

    fn has(&self, name: &str) -> bool {
        self.params.iter().any(|p| p.name == name)
    }
}

/// Splits at the commas outside brackets.
fn split_top(s: &str) -> Vec<&str> {
    let (mut depth, mut start, mut out) = (0i32, 0usize, Vec::new());
    for (k, c) in s.char_indices() {
        match c {
            '(' | '[' | '{' => depth += 1,
            ')' | ']' | '}' => depth -= 1,
            ',' if depth == 0 => {
                out.push(&s[start..k]);
                start = k + 1;
            }
            _ => {}
        }
    }
    out.push(&s[start..]);
    out
}

/// How an old parameter name maps onto a new one (`Definition::rename`).
pub(crate) type Rename = fn(&str) -> Option<(&'static str, Option<usize>)>;

/// The element `name`'s arguments by parameter name, old spellings mapped (and warned of).
pub(crate) fn bind<'py>(
    py: Python<'py>,
    name: &str,
    sig: &Signature,
    legacy: &[&str],
    (rename, defaults): (Rename, &[(&str, &str)]),
    args: &Bound<'py, PyTuple>,
    kwargs: Option<&Bound<'py, PyDict>>,
) -> PyResult<Bound<'py, PyDict>> {
    let out = PyDict::new(py);
    let positional: Vec<&Param> = sig.positional().collect();
    let mut old: Vec<(String, Bound<'py, PyAny>)> = Vec::new();
    let mut warned = false;
    if args.len() > positional.len() {
        if args.len() > legacy.len() {
            let names: Vec<&str> = positional.iter().map(|p| p.name.as_str()).collect();
            return Err(PyTypeError::new_err(format!(
                "{name}() takes at most {} positional arguments ({}) but {} were given; \
                 physical parameters are keyword-only: {name}{}",
                positional.len(),
                names.join(", "),
                args.len(),
                sig.text
            )));
        }
        warn(
            py,
            &format!(
                "{name}({}): this positional form is deprecated; the dofs come first and the \
                 physical parameters are keyword-only: {name}{}",
                legacy[..args.len()].join(", "),
                sig.text
            ),
        )?;
        warned = true;
        for (k, value) in args.iter().enumerate() {
            old.push((legacy[k].to_owned(), value));
        }
    } else {
        for (p, value) in positional.iter().zip(args.iter()) {
            out.set_item(&p.name, value)?;
        }
    }
    if let Some(kwargs) = kwargs {
        for (key, value) in kwargs.iter() {
            let key: String = key.extract()?;
            old.push((key, value));
        }
    }
    let mut moved: Vec<(&'static str, usize, Bound<'py, PyAny>)> = Vec::new();
    for (key, value) in old {
        if sig.has(&key) {
            if out.contains(&key)? {
                return Err(PyTypeError::new_err(format!(
                    "{name}() got multiple values for argument `{key}`"
                )));
            }
            out.set_item(&key, value)?;
            continue;
        }
        match rename(&key) {
            Some((new, position)) => {
                if !warned {
                    warn(
                        py,
                        &format!(
                            "{name}: `{key}` is deprecated, use `{new}`: {name}{}",
                            sig.text
                        ),
                    )?;
                    warned = true;
                }
                match position {
                    Some(k) => moved.push((new, k, value)),
                    None => {
                        if out.contains(new)? {
                            return Err(PyTypeError::new_err(format!(
                                "{name}() got `{key}` and `{new}` (the same parameter)"
                            )));
                        }
                        out.set_item(new, value)?;
                    }
                }
            }
            None => {
                return Err(PyTypeError::new_err(format!(
                    "{name}() got an unexpected keyword argument `{key}`: {name}{}",
                    sig.text
                )))
            }
        }
    }
    gather(py, name, &out, moved)?;
    for p in &sig.params {
        if p.required && !out.contains(&p.name)? {
            if let Some((_, value)) = defaults.iter().find(|(n, _)| *n == p.name) {
                warn(
                    py,
                    &format!(
                        "{name}: `{}` is required (a physical value has no default); the \
                         previous release's default {value} is used for now: {name}{}",
                        p.name, sig.text
                    ),
                )?;
                let v: serde_json::Value =
                    serde_json::from_str(value).map_err(|e| PyTypeError::new_err(e.to_string()))?;
                out.set_item(&p.name, crate::values::to_python(py, &v)?)?;
                continue;
            }
            let kind = if p.keyword_only { "keyword " } else { "" };
            return Err(PyTypeError::new_err(format!(
                "{name}() missing required {kind}argument `{}`: {name}{}",
                p.name, sig.text
            )));
        }
    }
    Ok(out)
}

/// Old parameters that became entries of a tuple (`dof_x`, `dof_y` -> `dofs`), trailing
/// None left out.
fn gather<'py>(
    py: Python<'py>,
    name: &str,
    out: &Bound<'py, PyDict>,
    moved: Vec<(&'static str, usize, Bound<'py, PyAny>)>,
) -> PyResult<()> {
    let mut targets: Vec<&'static str> = moved.iter().map(|m| m.0).collect();
    targets.dedup();
    for target in targets {
        // what the new spelling gave already (a dof given positionally: entry 0)
        let mut items: Vec<Bound<'py, PyAny>> = match out.get_item(target)? {
            None => Vec::new(),
            Some(v)
                if v.is_instance_of::<PyTuple>() || v.is_instance_of::<pyo3::types::PyList>() =>
            {
                v.try_iter()?.collect::<PyResult<_>>()?
            }
            Some(v) => vec![v],
        };
        let size = moved
            .iter()
            .filter(|m| m.0 == target)
            .map(|m| m.1 + 1)
            .max()
            .unwrap_or(0);
        while items.len() < size {
            items.push(py.None().into_bound(py));
        }
        for (_, k, value) in moved.iter().filter(|m| m.0 == target) {
            if !items[*k].is_none() {
                return Err(PyTypeError::new_err(format!(
                    "{name}() got entry {k} of `{target}` twice (with its old spelling)"
                )));
            }
            items[*k] = value.clone();
        }
        while items.last().is_some_and(|v| v.is_none()) && items.len() > 1 {
            items.pop();
        }
        out.set_item(target, PyTuple::new(py, items)?)?;
    }
    Ok(())
}

/// A `DeprecationWarning` pointing at the caller's line.
pub(crate) fn warn(py: Python<'_>, message: &str) -> PyResult<()> {
    let category = py.get_type::<PyDeprecationWarning>();
    PyErr::warn(py, &category, &std::ffi::CString::new(message)?, 1)
}
