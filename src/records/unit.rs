//! The unit a record's accelerations are written in, from its many spellings
//! in files, headers and query strings.

/// The unit of a record's accelerations as written in its file.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Unit {
    /// Multiples of g, converted with [`G_M_S2`](super::G_M_S2).
    G,
    /// m/s².
    MetresPerSecondSquared,
    /// cm/s² (gal).
    CentimetresPerSecondSquared,
}

/// The spellings [`Unit::parse`] accepts, for error messages.
pub const ACCEPTED_UNITS: &str =
    "g, m/s2 (m/s^2, m/s², m/s/s, mps2), cm/s2 (cm/s^2, cm/s², cm/s/s, cm/sec/sec, gal)";

impl Unit {
    /// The unit spelled `text`: case and spaces do not matter, and `²`,
    /// `^2`, `2`, `/s/s` and `/sec/sec` all say "squared".
    pub fn parse(text: &str) -> Option<Unit> {
        let key: String = text
            .chars()
            .filter(|c| !c.is_whitespace())
            .flat_map(char::to_lowercase)
            .collect();
        match key.as_str() {
            "g" => Some(Unit::G),
            "m/s2" | "m/s^2" | "m/s²" | "m/s/s" | "m/s**2" | "m/sec2" | "m/sec^2" | "m/sec²"
            | "m/sec/sec" | "m/sec**2" | "mps2" | "ms-2" | "m.s-2" | "m·s-2" => {
                Some(Unit::MetresPerSecondSquared)
            }
            "cm/s2" | "cm/s^2" | "cm/s²" | "cm/s/s" | "cm/s**2" | "cm/sec2" | "cm/sec^2"
            | "cm/sec²" | "cm/sec/sec" | "cm/sec**2" | "cmps2" | "cms-2" | "cm.s-2" | "cm·s-2"
            | "gal" | "gals" => Some(Unit::CentimetresPerSecondSquared),
            _ => None,
        }
    }

    /// The canonical spelling: `g`, `m/s2` or `cm/s2` (what [`parse`](Unit::parse)
    /// reads back, and what a job spec's `unit` says for the first two).
    pub fn as_str(self) -> &'static str {
        match self {
            Unit::G => "g",
            Unit::MetresPerSecondSquared => "m/s2",
            Unit::CentimetresPerSecondSquared => "cm/s2",
        }
    }

    /// The unit written in a column's header name, when it is clear:
    /// inside brackets (`acc (g)`, `acceleration [cm/s2]`) or as the last
    /// `_`-separated words (`acc_g`, `a_m_s2`, `accel_gal`). A bare name
    /// (`g`, `acceleration`) says nothing.
    pub fn in_column_name(name: &str) -> Option<Unit> {
        if let Some(inside) = bracketed(name) {
            return Unit::parse(inside).or_else(|| Unit::parse(&inside.replace('_', "/")));
        }
        let words: Vec<&str> = name
            .split(|c: char| c == '_' || c == '-' || c.is_whitespace())
            .filter(|w| !w.is_empty())
            .collect();
        // The longest tail of words that spells a unit, the name's first word
        // (what is measured) excluded.
        (1..words.len()).find_map(|start| Unit::parse(&words[start..].join("/")))
    }
}

impl std::fmt::Display for Unit {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(self.as_str())
    }
}

/// The text inside the last `(…)` or `[…]` of `name`, if any.
pub fn bracketed(name: &str) -> Option<&str> {
    let close = name.rfind([')', ']'])?;
    let open_char = if name[close..].starts_with(')') {
        '('
    } else {
        '['
    };
    let open = name[..close].rfind(open_char)?;
    Some(name[open + 1..close].trim())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_documented_spelling_parses_to_its_unit() {
        for g in ["g", "G", " g "] {
            assert_eq!(Unit::parse(g), Some(Unit::G), "{g}");
        }
        for m in [
            "m/s2",
            "m/s^2",
            "m/s²",
            "m/s/s",
            "m/sec2",
            "mps2",
            "M/S2",
            "m / s ^ 2",
        ] {
            assert_eq!(Unit::parse(m), Some(Unit::MetresPerSecondSquared), "{m}");
        }
        for cm in [
            "cm/s2",
            "cm/s^2",
            "cm/s²",
            "cm/s/s",
            "cm/sec/sec",
            "cm/sec^2",
            "gal",
            "gals",
            "CM/S/S",
            "CM/SEC/SEC",
            "Gal",
        ] {
            assert_eq!(
                Unit::parse(cm),
                Some(Unit::CentimetresPerSecondSquared),
                "{cm}"
            );
        }
        for none in ["", "m", "m/s", "cm/s", "mg", "ft/s2", "in/s/s", "kg"] {
            assert_eq!(Unit::parse(none), None, "{none}");
        }
    }

    #[test]
    fn the_canonical_spelling_reads_back_as_the_same_unit() {
        for u in [
            Unit::G,
            Unit::MetresPerSecondSquared,
            Unit::CentimetresPerSecondSquared,
        ] {
            assert_eq!(Unit::parse(u.as_str()), Some(u));
        }
    }

    #[test]
    fn column_names_state_their_unit_in_brackets_or_a_suffix() {
        for (name, unit) in [
            ("acc_g", Some(Unit::G)),
            ("acc (g)", Some(Unit::G)),
            ("Acc(G)", Some(Unit::G)),
            (
                "acceleration [cm/s2]",
                Some(Unit::CentimetresPerSecondSquared),
            ),
            ("a_m_s2", Some(Unit::MetresPerSecondSquared)),
            ("acc_cm_s2", Some(Unit::CentimetresPerSecondSquared)),
            ("acc [m_s2]", Some(Unit::MetresPerSecondSquared)),
            ("accel_gal", Some(Unit::CentimetresPerSecondSquared)),
            ("acc mps2", Some(Unit::MetresPerSecondSquared)),
            ("acceleration", None),
            ("g", None),
            ("acc_x", None),
            ("acc (counts)", None),
        ] {
            assert_eq!(Unit::in_column_name(name), unit, "{name}");
        }
    }
}
