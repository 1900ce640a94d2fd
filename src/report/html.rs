//! The HTML page: escaping, and a builder that puts headings, paragraphs, tables, figures and
//! settings into one self-contained document (inline CSS, inline SVG, no script, nothing
//! fetched: it opens from a file, offline, in any browser).

/// `text` with the five characters that HTML gives meaning escaped; safe in element content and
/// in quoted attribute values alike.
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

/// One table cell: its text (escaped when written) and how it is shown.
#[derive(Clone, Debug, PartialEq)]
pub struct Cell {
    /// The cell's text.
    pub text: String,
    /// A CSS class: `num` (right-aligned figures), `paper` (a number quoted from the paper),
    /// `note` (a remark), or none.
    pub class: Option<&'static str>,
}

impl Cell {
    /// A cell of plain text.
    pub fn text(t: impl Into<String>) -> Cell {
        Cell {
            text: t.into(),
            class: None,
        }
    }

    /// A cell of figures, right-aligned.
    pub fn num(t: impl Into<String>) -> Cell {
        Cell {
            text: t.into(),
            class: Some("num"),
        }
    }

    /// A number quoted from the paper (set apart in colour).
    pub fn paper(t: impl Into<String>) -> Cell {
        Cell {
            text: t.into(),
            class: Some("paper"),
        }
    }

    /// A remark (small, muted).
    pub fn note(t: impl Into<String>) -> Cell {
        Cell {
            text: t.into(),
            class: Some("note"),
        }
    }
}

/// A table: a header row and body rows.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Table {
    /// Column headings.
    pub header: Vec<String>,
    /// Rows of cells (one per heading).
    pub rows: Vec<Vec<Cell>>,
}

impl Table {
    /// A table with these headings and no rows yet.
    pub fn new<S: Into<String>>(header: impl IntoIterator<Item = S>) -> Table {
        Table {
            header: header.into_iter().map(Into::into).collect(),
            rows: Vec::new(),
        }
    }

    /// Appends a row.
    pub fn row(&mut self, cells: Vec<Cell>) {
        self.rows.push(cells);
    }
}

/// How every page begins its generator tag (the version follows): what tells a page this
/// command wrote from any other file (`report::write_report` replaces only such a page).
pub const GENERATOR_META: &str = "<meta name=\"generator\" content=\"glassscan ";

/// The page's style: readable tables, figures that fit the window, paper numbers set apart.
const STYLE: &str = "\
body{font-family:system-ui,-apple-system,'Segoe UI',sans-serif;margin:2rem auto;max-width:72rem;\
padding:0 1rem;color:#1d1d1f;line-height:1.45}\
h1{font-size:1.6rem;margin-bottom:.2rem}h2{font-size:1.25rem;margin-top:2.2rem;\
border-bottom:1px solid #ccc;padding-bottom:.2rem}h3{font-size:1.05rem;margin-top:1.5rem}\
p.sub{color:#555;margin-top:0}\
table{border-collapse:collapse;margin:.6rem 0 1rem;font-size:.9rem}\
th,td{border:1px solid #d0d0d0;padding:.25rem .55rem;vertical-align:top;text-align:left}\
th{background:#f2f2f4}td.num{text-align:right;font-variant-numeric:tabular-nums;white-space:nowrap}\
td.paper{background:#fff6e0;color:#6b4a00}td.note{color:#666;font-size:.85rem}\
figure{margin:1rem 0 1.6rem}figure svg{display:block;max-width:100%;height:auto;\
border:1px solid #e2e2e2}figcaption{font-size:.88rem;color:#444;margin-top:.3rem}\
pre{background:#f6f6f8;padding:.6rem;overflow:auto;font-size:.8rem}\
details{margin:.5rem 0}.source{font-size:.85rem;color:#6b4a00}";

/// The page being built.
#[derive(Debug)]
pub struct Page {
    title: String,
    body: String,
}

impl Page {
    /// A page with `title` as its heading and `subtitle` (e.g. the run directory) beneath.
    pub fn new(title: &str, subtitle: &str) -> Page {
        let mut body = String::new();
        body += &format!("<h1>{}</h1>\n", escape(title));
        body += &format!("<p class=\"sub\">{}</p>\n", escape(subtitle));
        Page {
            title: title.to_owned(),
            body,
        }
    }

    /// A section heading.
    pub fn h2(&mut self, text: &str) {
        self.body += &format!("<h2>{}</h2>\n", escape(text));
    }

    /// A sub-heading.
    pub fn h3(&mut self, text: &str) {
        self.body += &format!("<h3>{}</h3>\n", escape(text));
    }

    /// A paragraph of plain text.
    pub fn para(&mut self, text: &str) {
        self.body += &format!("<p>{}</p>\n", escape(text));
    }

    /// A paragraph naming where in the paper a quoted number comes from.
    pub fn source(&mut self, text: &str) {
        self.body += &format!("<p class=\"source\">{}</p>\n", escape(text));
    }

    /// A bulleted list of plain-text items.
    pub fn list(&mut self, items: &[String]) {
        self.body += "<ul>\n";
        for i in items {
            self.body += &format!("<li>{}</li>\n", escape(i));
        }
        self.body += "</ul>\n";
    }

    /// A table.
    pub fn table(&mut self, t: &Table) {
        self.body += "<table>\n<thead><tr>";
        for h in &t.header {
            self.body += &format!("<th>{}</th>", escape(h));
        }
        self.body += "</tr></thead>\n<tbody>\n";
        for row in &t.rows {
            self.body += "<tr>";
            for c in row {
                match c.class {
                    Some(class) => {
                        self.body += &format!("<td class=\"{class}\">{}</td>", escape(&c.text))
                    }
                    None => self.body += &format!("<td>{}</td>", escape(&c.text)),
                }
            }
            self.body += "</tr>\n";
        }
        self.body += "</tbody>\n</table>\n";
    }

    /// A figure: `svg` is an SVG document checked by `xml_check` (a chart of `svg`, or a file
    /// of the run read by `figure_file`), put inline as it is, with its caption.
    pub fn figure(&mut self, svg: &str, caption: &str) {
        self.body += "<figure>\n";
        self.body += svg.trim();
        self.body += &format!(
            "\n<figcaption>{}</figcaption>\n</figure>\n",
            escape(caption)
        );
    }

    /// A collapsed block of preformatted text (a scene file, a randomisation file).
    pub fn details_pre(&mut self, summary: &str, text: &str) {
        self.body += &format!(
            "<details><summary>{}</summary><pre>{}</pre></details>\n",
            escape(summary),
            escape(text)
        );
    }

    /// The whole document.
    pub fn finish(self) -> String {
        format!(
            "<!DOCTYPE html>\n<html lang=\"en\">\n<head>\n<meta charset=\"utf-8\"/>\n\
             <meta name=\"viewport\" content=\"width=device-width, initial-scale=1\"/>\n\
             {GENERATOR_META}{}\"/>\n\
             <link rel=\"icon\" href=\"data:,\"/>\n<title>{}</title>\n<style>{STYLE}</style>\n\
             </head>\n<body>\n{}<footer><p class=\"sub\">Written by <code>glassscan report</code> \
             from the run's files. Quoted numbers of the paper (Adrian &amp; Pham, \
             <i>Locating Transparent Objects to Millimetre Accuracy</i>) are shaded and name \
             their section and table.</p></footer>\n</body>\n</html>\n",
            escape(env!("CARGO_PKG_VERSION")),
            escape(&self.title),
            self.body
        )
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn escaping_covers_markup_and_both_quotes() {
        assert_eq!(
            escape("<a href=\"x\">R&D's</a>"),
            "&lt;a href=&quot;x&quot;&gt;R&amp;D&#39;s&lt;/a&gt;"
        );
        assert_eq!(escape("|BIP − p_e| ± 0.1 mm"), "|BIP − p_e| ± 0.1 mm");
        assert_eq!(escape(""), "");
    }

    #[test]
    fn a_page_escapes_every_text_and_is_well_formed() {
        let mut p = Page::new("A <study>", "dir/with & amp");
        p.h2("Results & <b>");
        p.para("x < y");
        let mut t = Table::new(["a<", "b"]);
        t.row(vec![Cell::num("1 & 2"), Cell::paper("<0.94>")]);
        p.table(&t);
        p.figure(
            "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"2\" height=\"2\"></svg>",
            "fig <1>",
        );
        p.details_pre("scene", "a = \"<b>\"");
        p.list(&["i<".into()]);
        let html = p.finish();
        assert!(html.starts_with("<!DOCTYPE html>"));
        assert!(html.contains("<title>A &lt;study&gt;</title>"));
        assert!(
            html.contains("<td class=\"num\">1 &amp; 2</td><td class=\"paper\">&lt;0.94&gt;</td>")
        );
        assert!(html.contains("<figcaption>fig &lt;1&gt;</figcaption>"));
        assert!(!html.contains("<b>"), "no text reaches the page unescaped");
        // Nothing is fetched: no URL but the empty data: icon.
        assert!(!html.contains("http:") || html.matches("http://").count() == 1);
        assert!(!html.contains("https:") && !html.contains("<script"));
        // The document without its doctype is well-formed XML (every element closed).
        let body = html.trim_start_matches("<!DOCTYPE html>\n");
        super::super::xml_check::check_well_formed(body).unwrap();
    }
}
