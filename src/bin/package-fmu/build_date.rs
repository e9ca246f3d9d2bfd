//! The date written as `generationDateAndTime`: the commit date of the sources, so that
//! the same commit gives the same modelDescription.xml bytes (not the build time).
//! Order: `git log -1 --format=%ct` in the source tree; else the environment variable
//! `SOURCE_DATE_EPOCH` (the reproducible-builds convention, for a tarball); else none
//! (the attribute is optional in FMI 2.0 and is then left out).

use std::path::Path;
use std::process::Command;

/// Seconds since 1970 of the last commit, or of SOURCE_DATE_EPOCH.
pub fn source_epoch(repo: &Path) -> Option<(i64, &'static str)> {
    let git = Command::new("git")
        .args(["log", "-1", "--format=%ct"])
        .current_dir(repo)
        .output()
        .ok()
        .filter(|o| o.status.success())
        .and_then(|o| String::from_utf8(o.stdout).ok())
        .and_then(|s| s.trim().parse::<i64>().ok());
    if let Some(t) = git {
        return Some((t, "commit date"));
    }
    std::env::var("SOURCE_DATE_EPOCH")
        .ok()
        .and_then(|s| s.trim().parse::<i64>().ok())
        .map(|t| (t, "SOURCE_DATE_EPOCH"))
}

/// `YYYY-MM-DDThh:mm:ssZ` (xs:dateTime in UTC) of a Unix time.
pub fn iso8601_utc(t: i64) -> String {
    let days = t.div_euclid(86_400);
    let secs = t.rem_euclid(86_400);
    // civil date from days since 1970-01-01 (H. Hinnant's algorithm)
    let z = days + 719_468;
    let era = z.div_euclid(146_097);
    let doe = z - era * 146_097;
    let yoe = (doe - doe / 1460 + doe / 36_524 - doe / 146_096) / 365;
    let doy = doe - (365 * yoe + yoe / 4 - yoe / 100);
    let mp = (5 * doy + 2) / 153;
    let d = doy - (153 * mp + 2) / 5 + 1;
    let m = if mp < 10 { mp + 3 } else { mp - 9 };
    let y = yoe + era * 400 + i64::from(m <= 2);
    format!(
        "{y:04}-{m:02}-{d:02}T{:02}:{:02}:{:02}Z",
        secs / 3600,
        secs % 3600 / 60,
        secs % 60
    )
}

/// The model description with `generationDateAndTime` added to the root element (unless
/// it has one already).
pub fn with_generation_date(xml: &str, date: Option<&str>) -> String {
    let tag = "<fmiModelDescription";
    match (date, xml.find(tag)) {
        (Some(d), Some(i)) if !xml.contains("generationDateAndTime=") => {
            let at = i + tag.len();
            format!("{} generationDateAndTime=\"{d}\"{}", &xml[..at], &xml[at..])
        }
        _ => xml.to_string(),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn known_dates() {
        // independent values: `date -u -d @0`, `@951782400` (leap day 2000), `@1798156800`
        assert_eq!(iso8601_utc(0), "1970-01-01T00:00:00Z");
        assert_eq!(iso8601_utc(951_782_400), "2000-02-29T00:00:00Z");
        assert_eq!(iso8601_utc(1_798_156_800 + 3661), "2026-12-25T01:01:01Z");
    }

    #[test]
    fn inserted_once() {
        let x =
            r#"<?xml version="1.0"?><fmiModelDescription fmiVersion="2.0"></fmiModelDescription>"#;
        let y = with_generation_date(x, Some("2026-01-02T03:04:05Z"));
        assert!(y.contains(
            r#"<fmiModelDescription generationDateAndTime="2026-01-02T03:04:05Z" fmiVersion"#
        ));
        assert_eq!(with_generation_date(&y, Some("1999-01-01T00:00:00Z")), y);
        assert_eq!(with_generation_date(x, None), x);
    }
}
