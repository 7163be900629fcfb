//! Facts that hold across formats: one motion, one id; the guards as `read`
//! applies them.

use super::*;

/// A short motion in g, as text: 0, 0.012, -0.034, 0.051, -0.027, 0.008,
/// -0.01, 0.
const MOTION_G: [&str; 8] = [
    "0", "0.012", "-0.034", "0.051", "-0.027", "0.008", "-0.01", "0",
];

fn opts() -> ReadOptions {
    ReadOptions::default()
}

fn at2_g() -> String {
    let mut text = String::from(
        "PEER NGA STRONG MOTION DATABASE RECORD\nTest event, station, 000\n\
         ACCELERATION TIME SERIES IN UNITS OF G\nNPTS=     8, DT=   .0100 SEC\n",
    );
    for (k, v) in MOTION_G.iter().enumerate() {
        text.push_str(&format!("  {v}"));
        if k % 5 == 4 {
            text.push('\n');
        }
    }
    text.push('\n');
    text
}

fn csv_g() -> String {
    let mut text = String::from("# Test event\ntime_s,acc_g\n");
    for (k, v) in MOTION_G.iter().enumerate() {
        text.push_str(&format!("{:.2},{v}\n", k as f64 * 0.01));
    }
    text
}

fn json_g() -> String {
    format!(
        r#"{{"name": "Test event", "dt": 0.01, "unit": "g", "acc": [{}]}}"#,
        MOTION_G.join(", ")
    )
}

#[test]
fn one_motion_in_at2_csv_and_json_in_g_has_one_id() {
    let ids: Vec<String> = [at2_g(), csv_g(), json_g()]
        .iter()
        .map(|text| read(text, &opts()).expect("reads").id())
        .collect();
    assert_eq!(ids[0], ids[1]);
    assert_eq!(ids[0], ids[2]);
    assert_eq!(ids[0].len(), 32);
    assert!(
        ids[0]
            .bytes()
            .all(|b| b.is_ascii_hexdigit() && !b.is_ascii_uppercase())
    );
}

#[test]
fn a_record_in_g_reads_to_the_samples_a_job_spec_in_g_would_hold() {
    // validate_ground_motion multiplies each sample by the block's g (9.81 by default).
    let r = read(&json_g(), &opts()).expect("reads");
    let spec: Vec<f64> = MOTION_G
        .iter()
        .map(|t| t.parse::<f64>().expect("number") * crate::dynamics::block::STANDARD_GRAVITY)
        .collect();
    assert_eq!(r.acc, spec);
}

#[test]
fn one_motion_in_cm_csv_and_m_json_has_one_id() {
    let cm = "t,acc (cm/s2)\n0,0\n0.01,1.23\n0.02,-4.56\n0.03,7.8\n0.04,-2.1\n0.05,0.07\n";
    let m = r#"{"dt": 0.01, "unit": "m/s2", "acc": [0, 0.0123, -0.0456, 0.078, -0.021, 0.0007]}"#;
    let (a, b) = (
        read(cm, &opts()).expect("reads"),
        read(m, &opts()).expect("reads"),
    );
    assert_eq!(a.acc, b.acc);
    assert_eq!(a.id(), b.id());
    // A different motion has a different id.
    let other =
        r#"{"dt": 0.01, "unit": "m/s2", "acc": [0, 0.0123, -0.0456, 0.078, -0.021, 0.0008]}"#;
    assert_ne!(a.id(), read(other, &opts()).expect("reads").id());
}

#[test]
fn record_id_counts_negative_zero_as_zero_and_depends_on_dt() {
    assert_eq!(record_id(0.01, &[0.0, 1.0]), record_id(0.01, &[-0.0, 1.0]));
    assert_ne!(record_id(0.01, &[0.0, 1.0]), record_id(0.02, &[0.0, 1.0]));
    assert_ne!(record_id(0.01, &[0.0, 1.0]), record_id(0.01, &[1.0, 0.0]));
    // blake3 of 0.01's bits then 1.0's bits, little-endian, first 16 bytes.
    let mut bytes = 0.01f64.to_bits().to_le_bytes().to_vec();
    bytes.extend_from_slice(&1.0f64.to_bits().to_le_bytes());
    let expected = blake3::hash(&bytes).to_hex()[..32].to_string();
    assert_eq!(record_id(0.01, &[1.0]), expected);
}

#[test]
fn a_cm_record_read_as_m_is_refused_naming_unit_with_the_hint() {
    // PGA 604 cm/s² = 61.6 g if read as m/s².
    let text = "t,acc\n0,0\n0.01,120.5\n0.02,-604.3\n0.03,310.2\n0.04,-45.0\n0.05,0\n";
    let o = ReadOptions {
        unit: Some(Unit::MetresPerSecondSquared),
        ..opts()
    };
    let e = read(text, &o).expect_err("refused");
    assert_eq!(e.field, "unit");
    assert!(e.message.contains("61.600 g"), "{}", e.message);
    assert!(e.message.contains("cm/s² read as m/s²?"), "{}", e.message);
    assert!(e.message.contains("allow_large_pga"), "{}", e.message);
    // Read in cm/s² the same file is fine.
    let o = ReadOptions {
        unit: Some(Unit::CentimetresPerSecondSquared),
        ..opts()
    };
    let r = read(text, &o).expect("reads");
    assert!(r.warnings.iter().all(|w| w.kind != "large_pga"));
}

#[test]
fn allow_large_pga_keeps_an_implausible_record_with_a_warning() {
    let text = "t,acc\n0,0\n0.01,120.5\n0.02,-604.3\n0.03,310.2\n0.04,-45.0\n0.05,0\n";
    let o = ReadOptions {
        unit: Some(Unit::MetresPerSecondSquared),
        allow_large_pga: true,
        ..opts()
    };
    let r = read(text, &o).expect("kept");
    assert_eq!(r.acc[2], -604.3);
    let w: Vec<_> = r
        .warnings
        .iter()
        .filter(|w| w.kind == "large_pga")
        .collect();
    assert_eq!(w.len(), 1);
    assert!(
        w[0].message.contains("cm/s² read as m/s²?"),
        "{}",
        w[0].message
    );
}

#[test]
fn a_three_g_record_reads_with_a_large_pga_warning() {
    let text = r#"{"dt": 0.01, "unit": "g", "acc": [0, 1.2, -3.0, 2.1, -0.4, 0]}"#;
    let r = read(text, &opts()).expect("reads");
    let w: Vec<_> = r
        .warnings
        .iter()
        .filter(|w| w.kind == "large_pga")
        .collect();
    assert_eq!(w.len(), 1);
    assert!(w[0].message.contains("3.000 g"), "{}", w[0].message);
}

#[test]
fn an_uncorrected_baseline_reads_with_a_drift_warning() {
    // 0.05 g held for 2 s: the ground ends at 0.98 m/s.
    let mut text = String::from("acc_g\n");
    for k in 0..=200 {
        text.push_str(if k % 3 == 0 { "0.049\n" } else { "0.0505\n" });
    }
    let o = ReadOptions {
        dt: Some(0.01),
        ..opts()
    };
    let r = read(&text, &o).expect("reads");
    let w: Vec<_> = r
        .warnings
        .iter()
        .filter(|w| w.kind == "baseline_drift")
        .collect();
    assert_eq!(w.len(), 1, "{:?}", r.warnings);
    assert!(w[0].message.contains("m/s"), "{}", w[0].message);
}

#[test]
fn a_record_with_its_velocity_back_at_zero_reads_without_warnings() {
    let r = read(&csv_g(), &opts()).expect("reads");
    assert!(r.warnings.is_empty(), "{:?}", r.warnings);
}

#[test]
fn one_sample_is_refused() {
    let text = r#"{"dt": 0.01, "unit": "g", "acc": [0.1]}"#;
    let e = read(text, &opts()).expect_err("refused");
    assert_eq!(e.field, "body");
    assert!(e.message.contains("at least 2"), "{}", e.message);
}

#[test]
fn a_dt_option_out_of_range_is_refused_naming_dt() {
    let o = ReadOptions {
        dt: Some(2.0),
        ..opts()
    };
    assert_eq!(read("0.1\n0.2\n", &o).expect_err("refused").field, "dt");
}

#[test]
fn the_name_option_overrides_the_files_name() {
    let o = ReadOptions {
        name: Some("mine".into()),
        ..opts()
    };
    assert_eq!(read(&at2_g(), &o).expect("reads").name, "mine");
    assert_eq!(
        read(&at2_g(), &opts()).expect("reads").name,
        "Test event, station, 000"
    );
}

#[test]
fn a_bom_and_crlf_change_nothing() {
    let plain = read(&csv_g(), &opts()).expect("reads");
    let windows = format!("\u{feff}{}", csv_g().replace('\n', "\r\n"));
    assert_eq!(read(&windows, &opts()).expect("reads"), plain);
    let at2 = format!("\u{feff}{}", at2_g().replace('\n', "\r\n"));
    assert_eq!(read(&at2, &opts()).expect("reads").acc, plain.acc);
}

#[test]
fn the_format_option_overrides_detection() {
    let o = ReadOptions {
        format: Some(Format::Csv),
        ..opts()
    };
    // An AT2 file read as columns fails on its header instead of being misread.
    assert!(read(&at2_g(), &o).is_err());
}

#[test]
fn an_error_displays_its_field_and_line() {
    let e = ReadError::body(Some(7), "bad");
    assert_eq!(e.to_string(), "body (line 7): bad");
    assert_eq!(
        ReadError::new("unit", "missing").to_string(),
        "unit: missing"
    );
}
