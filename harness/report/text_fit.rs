//! Fitting titles into the width of a picture without a font to measure with: the page names
//! `sans-serif` and the browser picks the face, so widths are bounded from above, glyph class by
//! glyph class, and a title that could overflow is wrapped onto more lines instead of being cut
//! at the picture's edges.

/// Upper bound of the advance width of `c` in ems for the usual sans-serif faces, checked for
/// every printable ASCII character against the advances of DejaVu Sans and Liberation Sans
/// (the faces behind `sans-serif` on Linux; Arial has Liberation's metrics): in 1/2048 em the
/// widest narrow glyph is DejaVu's `r` (842 < 0.42 em), the widest lowercase letter or digit
/// 1303 (< 0.65 em), the widest capital `Q` (1612 < 0.8 em), `W` 2025 and `@` 2079 (< 1.05
/// em). Anything outside ASCII counts as 1.05 em.
pub fn glyph_width_em(c: char) -> f64 {
    match c {
        'i' | 'j' | 'l' | 'f' | 't' | 'r' | 'I' | ' ' | '.' | ',' | ':' | ';' | '\'' | '|'
        | '!' | '(' | ')' | '[' | ']' | '/' | '-' => 0.42,
        'm' | 'w' | 'M' | 'W' | '%' | '@' | '&' | '#' | '=' | '<' | '>' | '+' | '~' | '^' | '*' => {
            1.05
        }
        'A'..='Z' => 0.8,
        c if c.is_ascii() => 0.65,
        _ => 1.05,
    }
}

/// Upper bound of the width of `text` in pixels at a font size of `font_px` pixels.
pub fn width_bound(text: &str, font_px: f64) -> f64 {
    text.chars().map(glyph_width_em).sum::<f64>() * font_px
}

/// `text` broken into lines no wider than `width` pixels at `font_px` ([`width_bound`]): at
/// spaces where possible, after a `/`, `-`, `_` or `,` inside a long word next, and between any
/// two characters as a last resort, so that no line overflows however narrow the picture.
pub fn wrap(text: &str, font_px: f64, width: f64) -> Vec<String> {
    let fits = |s: &str| width_bound(s, font_px) <= width;
    let mut lines: Vec<String> = Vec::new();
    let mut line = String::new();
    for word in text.split_whitespace() {
        let joined = if line.is_empty() {
            word.to_string()
        } else {
            format!("{line} {word}")
        };
        if fits(&joined) {
            line = joined;
            continue;
        }
        if !line.is_empty() {
            lines.push(std::mem::take(&mut line));
        }
        // The word alone: split where it breaks naturally, else anywhere.
        for piece in split_long_word(word, &fits) {
            if line.is_empty() || !fits(&format!("{line}{piece}")) {
                if !line.is_empty() {
                    lines.push(std::mem::take(&mut line));
                }
                line = piece;
            } else {
                line.push_str(&piece);
            }
        }
    }
    if !line.is_empty() || lines.is_empty() {
        lines.push(line);
    }
    lines
}

/// `word` cut after each `/`, `-`, `_` or `,` into pieces, each piece that still does not
/// `fit` cut further into the longest runs of characters that do (at least one character).
fn split_long_word(word: &str, fits: &impl Fn(&str) -> bool) -> Vec<String> {
    let mut pieces = Vec::new();
    let mut piece = String::new();
    for c in word.chars() {
        piece.push(c);
        if matches!(c, '/' | '-' | '_' | ',') {
            pieces.push(std::mem::take(&mut piece));
        }
    }
    if !piece.is_empty() {
        pieces.push(piece);
    }
    let mut out = Vec::new();
    for piece in pieces {
        let mut run = String::new();
        for c in piece.chars() {
            run.push(c);
            if !fits(&run) && run.chars().count() > 1 {
                run.pop();
                out.push(std::mem::take(&mut run));
                run.push(c);
            }
        }
        out.push(run);
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn short_text_stays_on_one_line() {
        assert_eq!(wrap("Work-precision", 17.7, 560.0), ["Work-precision"]);
        assert_eq!(wrap("", 17.7, 560.0), [""]);
    }

    /// Every line of a long title fits, and the words come back in order.
    #[test]
    fn long_text_wraps_into_lines_that_fit() {
        let title =
            "Work-precision by solver: contact/spheres-eccentric-frictionless, energy_after_separation";
        for width in [560.0, 340.0, 120.0, 5.0] {
            let lines = wrap(title, 17.7, width);
            assert!(lines.len() > 1, "{width}: {lines:?}");
            for line in &lines {
                assert!(
                    width_bound(line, 17.7) <= width || line.chars().count() == 1,
                    "{width}: {line:?} overflows"
                );
            }
            let rejoined: String = lines.concat().split_whitespace().collect();
            let original: String = title.split_whitespace().collect();
            assert_eq!(rejoined, original, "{width}");
        }
    }

    /// A long path without spaces breaks after its separators, not in mid-name.
    #[test]
    fn long_words_break_after_separators() {
        let lines = wrap("contact/spheres-eccentric-frictionless", 17.7, 200.0);
        assert!(lines.len() > 1, "{lines:?}");
        assert!(
            lines[0].ends_with('/') || lines[0].ends_with('-'),
            "{lines:?}"
        );
    }
}
