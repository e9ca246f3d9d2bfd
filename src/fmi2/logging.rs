//! Logging to the master: the log categories of the model description, which of them
//! SetDebugLogging enabled, and the one function that calls the master's logger (the
//! FMI 2.0 `fmi2CallbackLogger` with a message made safe for a printf-style C logger, or the
//! FMI 3.0 `fmi3LogMessageCallback`). Version-neutral: the status is [`Status`].

use super::model::Status;
use super::types::{Fmi2CallbackLogger, Fmi2ComponentEnvironment, Fmi2Status};
use super::variables::LOG_CATEGORIES;
use crate::fmi3::types::{Fmi3InstanceEnvironment, Fmi3LogMessageCallback, Fmi3Status};
use std::ffi::CString;

/// Log categories (same order as in the model description's LogCategories).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Category {
    /// logStatusError
    Error,
    /// logStatusWarning
    Warning,
    /// logEvents
    Events,
    /// logSolver
    Solver,
    /// logStatusDiscard (a discarded step: the model left its validity, the solver stopped)
    Discard,
    /// logStatusFatal
    Fatal,
}

/// Number of log categories (without logAll).
const N_CATEGORIES: usize = 6;

impl Category {
    fn name(self) -> &'static str {
        match self {
            Category::Error => "logStatusError",
            Category::Warning => "logStatusWarning",
            Category::Events => "logEvents",
            Category::Solver => "logSolver",
            Category::Discard => "logStatusDiscard",
            Category::Fatal => "logStatusFatal",
        }
    }
}

/// Make a message safe for a C logger that treats it as a printf format: '%' -> "%%",
/// NUL -> "\0" (two characters).
pub fn escape_message(s: &str) -> CString {
    let mut out = String::with_capacity(s.len() + 8);
    for c in s.chars() {
        match c {
            '%' => out.push_str("%%"),
            '\0' => out.push_str("\\0"),
            c => out.push(c),
        }
    }
    // No NUL is left, so this cannot fail; fall back to an empty string rather than panic.
    CString::new(out).unwrap_or_default()
}

/// The master's callback, in the shape of its FMI version.
#[derive(Debug, Clone, Copy)]
pub enum Sink {
    /// `fmi2CallbackLogger` (variadic, the message is a printf format) and the
    /// componentEnvironment.
    Fmi2(Fmi2CallbackLogger, Fmi2ComponentEnvironment),
    /// `fmi3LogMessageCallback` (the message is plain text) and the instanceEnvironment.
    Fmi3(Fmi3LogMessageCallback, Fmi3InstanceEnvironment),
}

/// Only '\0' -> "\0" (FMI 3.0: the message is not a format string).
fn escape_nul(s: &str) -> CString {
    CString::new(s.replace('\0', "\\0")).unwrap_or_default()
}

/// The master's logger for one instance, with the enabled categories.
pub struct Logger {
    name: CString,
    sink: Sink,
    categories: [bool; N_CATEGORIES],
    categories_at_instantiate: [bool; N_CATEGORIES],
}

impl Logger {
    /// The logger of instance `name` (passed to the callback as it came: only the message
    /// is a printf format).
    pub fn new(name: &str, sink: Sink, logging_on: bool) -> Logger {
        Logger {
            name: CString::new(name).unwrap_or_else(|_| escape_message(name)),
            sink,
            categories: [logging_on; N_CATEGORIES],
            categories_at_instantiate: [logging_on; N_CATEGORIES],
        }
    }

    /// Sends a message to the master's logger. Errors, discards and warnings (the reason
    /// for a status other than OK) are always sent; other messages only when their category
    /// is enabled by SetDebugLogging.
    pub fn log(&self, status: Status, category: Category, msg: &str) {
        let forced = status != Status::OK;
        if !forced && !self.categories[category as usize] {
            return;
        }
        let cat = escape_message(category.name());
        match self.sink {
            Sink::Fmi2(Some(logger), env) => {
                let m = escape_message(msg);
                // SAFETY: the master's callback with NUL-terminated strings that outlive the
                // call; the message contains no '%' conversion, so a printf-style logger reads
                // no varargs.
                unsafe {
                    logger(
                        env,
                        self.name.as_ptr(),
                        Fmi2Status::from(status),
                        cat.as_ptr(),
                        m.as_ptr(),
                    )
                };
            }
            Sink::Fmi3(Some(logger), env) => {
                let m = escape_nul(msg);
                // SAFETY: the master's callback with NUL-terminated strings that outlive the
                // call.
                unsafe { logger(env, Fmi3Status::from(status), cat.as_ptr(), m.as_ptr()) };
            }
            Sink::Fmi2(None, _) | Sink::Fmi3(None, _) => {}
        }
    }

    /// Whether a category is enabled (to skip formatting work).
    pub fn enabled(&self, category: Category) -> bool {
        self.categories[category as usize]
    }

    /// SetDebugLogging: FMI 2.0 (2.1.5), FMI 3.0 the same: loggingOn with categories logs only those
    /// categories; loggingOn = false switches the listed ones off and leaves the others.
    ///
    /// # Errors
    /// The first unknown category, with the list of known ones.
    pub fn set_categories(&mut self, on: bool, cats: &[&str]) -> Result<(), String> {
        if cats.is_empty() {
            self.categories = [on; N_CATEGORIES];
            return Ok(());
        }
        let mut new = if on {
            [false; N_CATEGORIES]
        } else {
            self.categories
        };
        for c in cats {
            match *c {
                "logAll" => new = [on; N_CATEGORIES],
                "logStatusError" => new[Category::Error as usize] = on,
                "logStatusWarning" => new[Category::Warning as usize] = on,
                "logEvents" => new[Category::Events as usize] = on,
                "logSolver" => new[Category::Solver as usize] = on,
                "logStatusDiscard" => new[Category::Discard as usize] = on,
                "logStatusFatal" => new[Category::Fatal as usize] = on,
                other => {
                    return Err(format!(
                        "unknown log category \"{other}\" (known: {})",
                        LOG_CATEGORIES.join(", ")
                    ))
                }
            }
        }
        self.categories = new;
        Ok(())
    }

    /// Reset: the categories as at instantiation.
    pub fn reset(&mut self) {
        self.categories = self.categories_at_instantiate;
    }
}
