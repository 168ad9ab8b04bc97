//! The self-contained HTML page: tables, inline SVG plots, the command and
//! version that made it. Everything that comes from a file is escaped.

/// Escapes text for HTML content and attribute values.
pub fn escape(text: &str) -> String {
    let mut out = String::with_capacity(text.len());
    for c in text.chars() {
        match c {
            '&' => out.push_str("&amp;"),
            '<' => out.push_str("&lt;"),
            '>' => out.push_str("&gt;"),
            '"' => out.push_str("&quot;"),
            '\'' => out.push_str("&#39;"),
            c => out.push(c),
        }
    }
    out
}

/// A page under construction.
#[derive(Debug, Default)]
pub struct Page {
    title: String,
    body: String,
}

impl Page {
    /// A page with this title.
    pub fn new(title: &str) -> Page {
        Page {
            title: title.to_string(),
            body: String::new(),
        }
    }

    /// A section heading.
    pub fn heading(&mut self, text: &str) {
        self.body.push_str(&format!("<h2>{}</h2>\n", escape(text)));
    }

    /// A paragraph of text.
    pub fn paragraph(&mut self, text: &str) {
        self.body.push_str(&format!("<p>{}</p>\n", escape(text)));
    }

    /// A table: a caption, the header cells, the rows.
    pub fn table(&mut self, caption: &str, header: &[String], rows: &[Vec<String>]) {
        self.body
            .push_str(&format!("<table>\n<caption>{}</caption>\n<tr>", escape(caption)));
        for h in header {
            self.body.push_str(&format!("<th>{}</th>", escape(h)));
        }
        self.body.push_str("</tr>\n");
        for r in rows {
            self.body.push_str("<tr>");
            for c in r {
                self.body.push_str(&format!("<td>{}</td>", escape(c)));
            }
            self.body.push_str("</tr>\n");
        }
        self.body.push_str("</table>\n");
    }

    /// A figure: SVG made by [`crate::plots`] (trusted: imutherm drew it,
    /// and every text in it was passed through plotters' own escaping) with
    /// a caption.
    pub fn figure(&mut self, svg: &str, caption: &str) {
        self.body.push_str(&format!(
            "<figure class=\"plot\">{svg}<figcaption>{}</figcaption></figure>\n",
            escape(caption)
        ));
    }

    /// A preformatted block (a command line).
    pub fn code(&mut self, text: &str) {
        self.body.push_str(&format!("<pre>{}</pre>\n", escape(text)));
    }

    /// The finished page.
    pub fn finish(&self) -> String {
        format!(
            "<!DOCTYPE html>\n<html lang=\"en\">\n<head>\n<meta charset=\"utf-8\">\n<title>{}</title>\n<style>{STYLE}</style>\n</head>\n<body>\n<h1>{}</h1>\n{}</body>\n</html>\n",
            escape(&self.title),
            escape(&self.title),
            self.body
        )
    }
}

const STYLE: &str = "body{font-family:sans-serif;max-width:1100px;margin:2em auto;padding:0 1em;color:#222}\
table{border-collapse:collapse;margin:1em 0}td,th{border:1px solid #bbb;padding:.25em .6em;text-align:right}\
th{background:#eee}caption{font-weight:bold;text-align:left;padding:.3em 0}figure.plot{display:inline-block;margin:.5em}\
figcaption{font-size:.9em;color:#555}pre{background:#f4f4f4;padding:.6em;overflow-x:auto}";

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn file_text_is_escaped() {
        let mut p = Page::new("report");
        p.table(
            "inputs",
            &["file".to_string()],
            &[vec!["<script>alert(1)</script>.txt".to_string()]],
        );
        let html = p.finish();
        assert!(html.contains("&lt;script&gt;alert(1)&lt;/script&gt;.txt"));
        assert!(!html.contains("<script>"));
    }
}
