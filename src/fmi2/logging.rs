//! Logging to the master: the log categories of the model description, which of them
//! fmi2SetDebugLogging enabled, and the one function that calls the master's logger with a
//! message made safe for a printf-style C logger.

use super::types::{Fmi2CallbackLogger, Fmi2ComponentEnvironment, Fmi2Status};
use super::variables::LOG_CATEGORIES;
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
}

impl Category {
    fn name(self) -> &'static str {
        match self {
            Category::Error => "logStatusError",
            Category::Warning => "logStatusWarning",
            Category::Events => "logEvents",
            Category::Solver => "logSolver",
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

/// The master's logger for one instance, with the enabled categories.
pub struct Logger {
    name: CString,
    callback: Fmi2CallbackLogger,
    env: Fmi2ComponentEnvironment,
    categories: [bool; 4],
    categories_at_instantiate: [bool; 4],
}

impl Logger {
    /// The logger of instance `name` (passed to the callback as it came: only the message
    /// is a printf format).
    pub fn new(
        name: &str,
        callback: Fmi2CallbackLogger,
        env: Fmi2ComponentEnvironment,
        logging_on: bool,
    ) -> Logger {
        Logger {
            name: CString::new(name).unwrap_or_else(|_| escape_message(name)),
            callback,
            env,
            categories: [logging_on; 4],
            categories_at_instantiate: [logging_on; 4],
        }
    }

    /// Sends a message to the master's logger. Errors, discards and warnings (the reason
    /// for a status other than OK) are always sent; other messages only when their category
    /// is enabled by fmi2SetDebugLogging.
    pub fn log(&self, status: Fmi2Status, category: Category, msg: &str) {
        let forced = matches!(
            status,
            Fmi2Status::Error | Fmi2Status::Fatal | Fmi2Status::Discard | Fmi2Status::Warning
        );
        if !forced && !self.categories[category as usize] {
            return;
        }
        if let Some(logger) = self.callback {
            let cat = escape_message(category.name());
            let m = escape_message(msg);
            // SAFETY: the master's callback with NUL-terminated strings that outlive the call;
            // the message contains no '%' conversion, so a printf-style logger reads no varargs.
            unsafe {
                logger(
                    self.env,
                    self.name.as_ptr(),
                    status,
                    cat.as_ptr(),
                    m.as_ptr(),
                )
            };
        }
    }

    /// Whether a category is enabled (to skip formatting work).
    pub fn enabled(&self, category: Category) -> bool {
        self.categories[category as usize]
    }

    /// fmi2SetDebugLogging: FMI 2.0 (2.1.5): loggingOn with categories logs only those
    /// categories; loggingOn = false switches the listed ones off and leaves the others.
    ///
    /// # Errors
    /// The first unknown category, with the list of known ones.
    pub fn set_categories(&mut self, on: bool, cats: &[&str]) -> Result<(), String> {
        if cats.is_empty() {
            self.categories = [on; 4];
            return Ok(());
        }
        let mut new = if on { [false; 4] } else { self.categories };
        for c in cats {
            match *c {
                "logAll" => new = [on; 4],
                "logStatusError" => new[Category::Error as usize] = on,
                "logStatusWarning" => new[Category::Warning as usize] = on,
                "logEvents" => new[Category::Events as usize] = on,
                "logSolver" => new[Category::Solver as usize] = on,
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

    /// fmi2Reset: the categories as at fmi2Instantiate.
    pub fn reset(&mut self) {
        self.categories = self.categories_at_instantiate;
    }
}
