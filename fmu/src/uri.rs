//! Resource locations as importers pass them: FMI 2 gives a URI (fmpy: `file:///a%20b/`,
//! percent-encoded; OMSimulator: `file:////a b/`, not encoded), FMI 3 a plain path with or
//! without a trailing slash. All become a directory path.

use std::path::PathBuf;

/// The directory a resource location names, or an error naming the value.
pub fn resource_dir(location: &str) -> Result<PathBuf, String> {
    let path = match location.strip_prefix("file:") {
        Some(rest) => {
            // file:/p, file:///p, file:////p and file://localhost/p all mean /p.
            let rest = rest.strip_prefix("//localhost").unwrap_or(rest);
            let trimmed = rest.trim_start_matches('/');
            percent_decode(&format!("/{trimmed}"))
                .ok_or_else(|| format!("resource location `{location}` has a bad %-escape"))?
        }
        None if location.contains("://") => {
            return Err(format!("resource location `{location}` is not a file URI"))
        }
        None => location.to_string(),
    };
    if path.is_empty() {
        return Err("empty resource location".into());
    }
    Ok(PathBuf::from(path))
}

fn percent_decode(s: &str) -> Option<String> {
    let bytes = s.as_bytes();
    let mut out = Vec::with_capacity(bytes.len());
    let mut i = 0;
    while i < bytes.len() {
        if bytes[i] == b'%' {
            let hex = std::str::from_utf8(bytes.get(i + 1..i + 3)?).ok()?;
            out.push(u8::from_str_radix(hex, 16).ok()?);
            i += 3;
        } else {
            out.push(bytes[i]);
            i += 1;
        }
    }
    String::from_utf8(out).ok()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn importer_variants_all_resolve() {
        let expect = PathBuf::from("/tmp/my fmu/resources/");
        for loc in [
            "file:///tmp/my%20fmu/resources/",
            "file:////tmp/my fmu/resources/",
            "file:/tmp/my%20fmu/resources/",
            "file://localhost/tmp/my%20fmu/resources/",
            "/tmp/my fmu/resources/",
        ] {
            assert_eq!(resource_dir(loc).unwrap(), expect, "{loc}");
        }
        assert_eq!(resource_dir("/tmp/r").unwrap(), PathBuf::from("/tmp/r"));
        assert!(resource_dir("http://example.org/x").is_err());
        assert!(resource_dir("file:///bad%zz")
            .unwrap_err()
            .contains("%-escape"));
    }
}
