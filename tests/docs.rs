//! The diagnostic pages show real output: each page's first `cell` example is checked as
//! `pick.cell` (with `tests/ui/` as its folder, so `support/...` files resolve) and the
//! result must equal the output pasted under `$ cellc check pick.cell`. Run with
//! `UPDATE_DOCS=1` to rewrite the pasted output after a deliberate wording change.

use cellc_schema::{FileError, Files};

/// `pick.cell` from the page; anything else from `tests/ui/`.
struct PageFiles<'a> {
    example: &'a str,
}

impl Files for PageFiles<'_> {
    fn read(&self, path: &str) -> Result<Vec<u8>, FileError> {
        if path == "pick.cell" {
            return Ok(self.example.as_bytes().to_vec());
        }
        std::fs::read(format!("tests/ui/{path}")).map_err(|_| FileError::NotFound)
    }
}

fn block_after<'a>(page: &'a str, fence: &str, from: usize) -> Option<(usize, usize, &'a str)> {
    let start = page[from..].find(fence)? + from + fence.len();
    let start = start + page[start..].find('\n')? + 1;
    let end = start + page[start..].find("```")?;
    Some((start, end, &page[start..end]))
}

#[test]
fn pages_show_real_output() {
    let update = std::env::var_os("UPDATE_DOCS").is_some();
    let mut stale = Vec::new();
    let mut checked = 0;
    for &code in cellc_lang::codes::ALL {
        let path = code.page_path();
        let Ok(page) = std::fs::read_to_string(&path) else {
            continue;
        };
        let Some(marker) = page.find("$ cellc check pick.cell") else {
            continue;
        };
        let Some((_, _, example)) = block_after(&page, "```cell", 0) else {
            stale.push(format!("{path}: no ```cell example"));
            continue;
        };
        let compilation =
            cellc_driver::compile(&PageFiles { example }, "pick.cell", &Default::default());
        let mut real = cellc::render::human(
            &compilation.diagnostics,
            &compilation.sources,
            cellc::render::Color::Never,
        );
        real.push_str(&cellc::render::summary(&compilation.diagnostics));
        real.push('\n');
        let expected = format!("$ cellc check pick.cell\n{real}");
        let block_start = page[..marker]
            .rfind("```text\n")
            .map(|i| i + "```text\n".len())
            .unwrap_or(marker);
        let block_end = marker + page[marker..].find("```").unwrap_or(page.len() - marker);
        checked += 1;
        if page[block_start..block_end] != expected {
            if update {
                let new_page =
                    format!("{}{}{}", &page[..block_start], expected, &page[block_end..]);
                std::fs::write(&path, new_page).expect("page is writable");
            } else {
                stale.push(format!(
                    "{path}: output differs from `cellc check` (run with UPDATE_DOCS=1)"
                ));
            }
        }
        assert!(
            compilation.diagnostics.iter().any(|d| d.code == code),
            "{path}: the example does not produce {}",
            code.as_str()
        );
    }
    assert!(checked >= 30, "only {checked} pages have examples");
    assert!(stale.is_empty(), "{}", stale.join("\n"));
}
