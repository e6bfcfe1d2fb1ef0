//! Text formatting shared by the HTML page, the Markdown summary and the plot axes, so that a
//! number reads the same everywhere.

/// Significant figures of the numbers in tables: enough to compare an error with its tolerance.
const TABLE_DIGITS: usize = 4;
/// Significant figures of axis tick labels: ticks are round numbers, short labels avoid overlap.
const TICK_DIGITS: usize = 3;

/// A table number: four significant figures without trailing zeros (`0.05`, not `0.05000`),
/// scientific notation outside `[1e-3, 1e5)`.
pub fn num(v: f64) -> String {
    significant(v, TABLE_DIGITS)
}

/// An axis tick label: like [`num`] with three figures, short enough not to collide.
pub fn tick(v: f64) -> String {
    significant(v, TICK_DIGITS)
}

/// A duration in seconds, e.g. `1.234 s`.
pub fn seconds(v: f64) -> String {
    format!("{} s", num(v))
}

/// Formats `v` with at most `digits` significant figures, fixed-point for moderate magnitudes
/// and scientific notation otherwise, so that tiny errors and large forces both stay readable.
fn significant(v: f64, digits: usize) -> String {
    if v.is_nan() {
        return "NaN".to_string();
    }
    if v.is_infinite() {
        return if v > 0.0 { "inf" } else { "-inf" }.to_string();
    }
    if v == 0.0 {
        return "0".to_string();
    }
    let magnitude = v.abs().log10().floor() as i32;
    if (-3..5).contains(&magnitude) {
        let decimals = (digits as i32 - 1 - magnitude).max(0) as usize;
        trim_fraction(&format!("{v:.decimals$}"))
    } else {
        let text = format!("{:.*e}", digits - 1, v);
        let (mantissa, exponent) = text.split_once('e').unwrap_or((&text, "0"));
        format!("{}e{exponent}", trim_fraction(mantissa))
    }
}

/// Removes trailing zeros of a fractional part, and the point itself when nothing is left.
fn trim_fraction(text: &str) -> String {
    if text.contains('.') {
        text.trim_end_matches('0').trim_end_matches('.').to_string()
    } else {
        text.to_string()
    }
}

/// Escapes text for HTML element content and attribute values: case messages carry solver
/// output, which may contain `<`, `>` and `&`.
pub fn html(text: &str) -> String {
    let mut out = String::with_capacity(text.len());
    for c in text.chars() {
        match c {
            '<' => out.push_str("&lt;"),
            '>' => out.push_str("&gt;"),
            '&' => out.push_str("&amp;"),
            '"' => out.push_str("&quot;"),
            '\'' => out.push_str("&#39;"),
            other => out.push(other),
        }
    }
    out
}

/// Makes text safe inside a Markdown table cell: one line, no column separators.
pub fn markdown_cell(text: &str) -> String {
    text.replace('|', "\\|")
        .split_whitespace()
        .collect::<Vec<_>>()
        .join(" ")
}

/// The first line of `text`, cut to `max` characters with an ellipsis, for one-line summaries.
pub fn first_line(text: &str, max: usize) -> String {
    let line = text
        .lines()
        .find(|l| !l.trim().is_empty())
        .unwrap_or("")
        .trim();
    if line.chars().count() > max {
        let cut: String = line.chars().take(max.saturating_sub(1)).collect();
        format!("{cut}…")
    } else {
        line.to_string()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn numbers_keep_at_most_four_significant_figures() {
        assert_eq!(num(123.456), "123.5");
        assert_eq!(num(0.0123456), "0.01235");
        assert_eq!(num(1.5e-7), "1.5e-7");
        assert_eq!(num(0.05), "0.05");
        assert_eq!(num(-2.34567e8), "-2.346e8");
        assert_eq!(num(0.0), "0");
        assert_eq!(num(f64::NAN), "NaN");
    }

    #[test]
    fn ticks_are_trimmed() {
        assert_eq!(tick(0.5), "0.5");
        assert_eq!(tick(100.0), "100");
        assert_eq!(tick(1e-4), "1e-4");
        assert_eq!(tick(2.5e6), "2.5e6");
    }

    #[test]
    fn html_is_escaped() {
        assert_eq!(html("<a & 'b'>"), "&lt;a &amp; &#39;b&#39;&gt;");
    }
}
