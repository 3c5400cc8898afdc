//! The process-mining paper's conversion rules, one test each, on small hand-made logs.

use super::*;
use std::path::{Path, PathBuf};

const MAP: &str = "%IX0.1 in ll\n%IX0.2 in ml\n%QX0.0 out inlet\n%QX0.1 out outlet\n";

fn mapping() -> Mapping {
    Mapping::parse(Path::new("m.map"), MAP).unwrap()
}

/// Runs a log given as text through the conversion; returns the traces as
/// `(activity, class, time)` lists.
fn traces(log: &str, reset: &str) -> Vec<Vec<(String, &'static str, f64)>> {
    struct Collect(Vec<Vec<(String, &'static str, f64)>>);
    impl EventSink for Collect {
        fn begin_trace(&mut self, case: usize) -> std::io::Result<()> {
            assert_eq!(case, self.0.len() + 1, "cases are numbered 1, 2, ...");
            self.0.push(Vec::new());
            Ok(())
        }
        fn event(&mut self, e: &Event) -> std::io::Result<()> {
            let t = self.0.last_mut().expect("an event inside a trace");
            t.push((e.activity(), e.class.label(), e.time));
            Ok(())
        }
        fn end_trace(&mut self) -> std::io::Result<()> {
            Ok(())
        }
    }
    let m = mapping();
    let reader = LogReader::new(PathBuf::from("log.csv"), log.as_bytes(), &m, false).unwrap();
    let reset = ResetActivity::parse(reset, &m).unwrap();
    let mut c = Collect(Vec::new());
    convert(reader, &m, &reset, &mut [&mut c]).unwrap();
    c.0
}

fn ev(activity: &str, class: &'static str, time: f64) -> (String, &'static str, f64) {
    (activity.to_string(), class, time)
}

#[test]
fn changes_of_one_class_at_one_timestamp_merge_in_mapping_order() {
    let log = "timestamp,address,value\n1,%IX0.2,1\n1,%IX0.1,1\n2,%QX0.1,1\n2,%QX0.0,1\n";
    assert_eq!(
        traces(log, "%IX0.1 false"),
        [vec![
            ev("%IX0.1 true + %IX0.2 true", "input", 1.0),
            ev("%QX0.0 true + %QX0.1 true", "output", 2.0),
        ]]
    );
}

#[test]
fn inputs_and_outputs_at_one_timestamp_stay_apart_inputs_first() {
    // The output row comes first in the file; the PLC still read before it wrote.
    let log = "timestamp,address,value\n1,%QX0.0,1\n1,%IX0.1,1\n";
    assert_eq!(
        traces(log, "%IX0.1 false"),
        [vec![
            ev("%IX0.1 true", "input", 1.0),
            ev("%QX0.0 true", "output", 1.0)
        ]]
    );
}

#[test]
fn a_value_that_does_not_change_gives_no_event() {
    // Long format: a row repeating the value; wide format: repeated scans.
    let long = "timestamp,address,value\n1,%IX0.1,1\n2,%IX0.1,1\n3,%IX0.2,0\n4,%IX0.2,1\n";
    assert_eq!(
        traces(long, "%IX0.1 false"),
        [vec![
            ev("%IX0.1 true", "input", 1.0),
            ev("%IX0.2 true", "input", 4.0)
        ]]
    );
    let wide = "timestamp,ll,ml,inlet,outlet\n0,0,0,1,0\n1,0,0,1,0\n2,1,0,1,0\n3,1,0,1,0\n";
    assert_eq!(
        traces(wide, "%IX0.1 false"),
        [vec![
            ev("%QX0.0 true", "output", 0.0),
            ev("%IX0.1 true", "input", 2.0)
        ]]
    );
}

#[test]
fn the_first_sample_is_compared_with_all_false() {
    // Signals already true in the first row are events at its timestamp; false ones are not.
    let wide = "timestamp,ll,ml,inlet,outlet\n5,1,0,0,1\n6,1,0,0,1\n";
    assert_eq!(
        traces(wide, "%IX0.1 false"),
        [vec![
            ev("%IX0.1 true", "input", 5.0),
            ev("%QX0.1 true", "output", 5.0)
        ]]
    );
    let zeros = "timestamp,ll,ml,inlet,outlet\n5,0,0,0,0\n";
    assert!(traces(zeros, "%IX0.1 false").is_empty());
}

#[test]
fn a_change_undone_within_one_timestamp_gives_no_event() {
    let long = "timestamp,address,value\n1,%IX0.1,1\n1,%IX0.1,0\n2,%IX0.2,1\n";
    assert_eq!(
        traces(long, "%IX0.1 false"),
        [vec![ev("%IX0.2 true", "input", 2.0)]]
    );
}

#[test]
fn the_log_is_sliced_into_traces_at_the_reset_activity() {
    // Two fill/drain cycles of a tank: the reset (%IX0.1 false, the tank ran empty) opens a
    // new trace; the events before the first reset are the first trace.
    let log = "timestamp,address,value
0,%QX0.0,1
1,%IX0.1,1
2,%IX0.2,1
2,%QX0.0,0
2,%QX0.1,1
3,%IX0.2,0
4,%IX0.1,0
4,%QX0.1,0
4,%QX0.0,1
5,%IX0.1,1
6,%IX0.1,0
";
    let t = traces(log, "%IX0.1 false");
    let names: Vec<Vec<&str>> = t
        .iter()
        .map(|tr| tr.iter().map(|e| e.0.as_str()).collect())
        .collect();
    assert_eq!(
        names,
        [
            vec![
                "%QX0.0 true",
                "%IX0.1 true",
                "%IX0.2 true",
                "%QX0.0 false + %QX0.1 true",
                "%IX0.2 false"
            ],
            vec!["%IX0.1 false", "%QX0.0 true + %QX0.1 false", "%IX0.1 true"],
            vec!["%IX0.1 false"],
        ]
    );
}

#[test]
fn a_merged_event_containing_the_reset_change_is_a_reset() {
    let log = "timestamp,address,value\n1,%IX0.1,1\n1,%IX0.2,1\n2,%IX0.1,0\n2,%IX0.2,0\n";
    let t = traces(log, "ll false");
    assert_eq!(t.len(), 2);
    assert_eq!(t[1], [ev("%IX0.1 false + %IX0.2 false", "input", 2.0)]);
    // A reset of two changes needs both.
    let t = traces(log, "%IX0.1 false + %IX0.2 false");
    assert_eq!(t.len(), 2);
    let t = traces(log, "%IX0.1 false + %IX0.2 true");
    assert_eq!(t.len(), 1);
}

#[test]
fn bad_reset_activities_are_explained() {
    let m = mapping();
    let msg = |text: &str| ResetActivity::parse(text, &m).unwrap_err().to_string();
    assert_eq!(
        msg("%IX9.9 false"),
        "reset activity '%IX9.9 false': '%IX9.9' is not an address or name of the mapping"
    );
    assert_eq!(
        msg("%IX0.1"),
        "reset activity '%IX0.1': '%IX0.1' is not 'ADDRESS VALUE' (e.g. '%IX0.1 false')"
    );
    assert_eq!(
        msg("%IX0.1 off"),
        "reset activity '%IX0.1 off': 'off' is not true, false, 1 or 0"
    );
    assert_eq!(
        msg("%IX0.1 false + %QX0.0 true"),
        "reset activity '%IX0.1 false + %QX0.0 true': mixes inputs and outputs, which never merge into one event"
    );
    let r = ResetActivity::parse("ll 0", &m).unwrap();
    assert_eq!(r.to_string(), "%IX0.1 false");
}

#[test]
fn timestamps_become_utc_date_times() {
    assert_eq!(iso_time(0.0), "1970-01-01T00:00:00.000+00:00");
    assert_eq!(iso_time(12.5), "1970-01-01T00:00:12.500+00:00");
    assert_eq!(iso_time(1_700_000_000.25), "2023-11-14T22:13:20.250+00:00");
    assert_eq!(iso_time(951_782_400.0), "2000-02-29T00:00:00.000+00:00");
    assert_eq!(iso_time(-0.5), "1969-12-31T23:59:59.500+00:00");
}

const TANK_LOG: &str = "timestamp,address,value
0,%QX0.0,1
1,%IX0.1,1
2,%QX0.0,0
2,%QX0.1,1
3,%IX0.1,0
3,%QX0.1,0
";

#[test]
fn xes_and_csv_files_are_written_and_well_formed() {
    let dir = tempfile::tempdir().unwrap();
    let log = dir.path().join("tank.csv");
    std::fs::write(&log, TANK_LOG).unwrap();
    let m = mapping();
    let reset = ResetActivity::parse("%IX0.1 false", &m).unwrap();
    let (xes_path, csv_path) = (dir.path().join("o/t.xes"), dir.path().join("o/t.csv"));
    let s = write_event_logs(&log, &m, &reset, false, &xes_path, &csv_path).unwrap();
    assert_eq!((s.traces, s.events, s.resets), (2, 5, 1));
    let xes = std::fs::read_to_string(&xes_path).unwrap();
    insta::assert_snapshot!("tank_xes", xes);
    // The IEEE 1849 schema: xes.version is an xs:decimal, classifier names are xs:NCName.
    let version = xes
        .split("xes.version=\"")
        .nth(1)
        .and_then(|r| r.split('"').next());
    assert!(
        version.is_some_and(|v| v.parse::<f64>().is_ok()),
        "{version:?}"
    );
    for name in xes.split("<classifier name=\"").skip(1) {
        let name = name.split('"').next().unwrap();
        let ncname = name
            .chars()
            .next()
            .is_some_and(|c| c.is_alphabetic() || c == '_')
            && name
                .chars()
                .all(|c| c.is_alphanumeric() || "_-.".contains(c));
        assert!(ncname, "classifier name {name:?} is not an NCName");
    }
    let els = xes::elements(&xes);
    assert_eq!(els.iter().filter(|(n, _)| n == "trace").count(), 2);
    assert_eq!(els.iter().filter(|(n, _)| n == "event").count(), 5);
    assert_eq!(
        std::fs::read_to_string(&csv_path).unwrap(),
        "case_id,activity,timestamp,class
1,%QX0.0 true,1970-01-01T00:00:00.000+00:00,output
1,%IX0.1 true,1970-01-01T00:00:01.000+00:00,input
1,%QX0.0 false + %QX0.1 true,1970-01-01T00:00:02.000+00:00,output
2,%IX0.1 false,1970-01-01T00:00:03.000+00:00,input
2,%QX0.1 false,1970-01-01T00:00:03.000+00:00,output
"
    );
}

#[test]
fn xes_attribute_values_are_escaped() {
    let mut x = xes::XesWriter::new(Vec::new(), "a <log> & \"more\"").unwrap();
    x.begin_trace(1).unwrap();
    x.event(&Event {
        time: 0.0,
        class: EventClass::Input,
        changes: vec![Change {
            address: "<x&y>".into(),
            value: true,
        }],
    })
    .unwrap();
    x.end_trace().unwrap();
    let text = String::from_utf8(x.finish().unwrap()).unwrap();
    let els = xes::elements(&text);
    let values: Vec<&str> = els
        .iter()
        .flat_map(|(_, a)| a.iter())
        .filter(|(k, _)| k == "value")
        .map(|(_, v)| v.as_str())
        .collect();
    assert!(values.contains(&"a <log> & \"more\""), "{values:?}");
    assert!(values.contains(&"<x&y> true"), "{values:?}");
}

#[test]
fn a_bad_row_names_file_and_line_and_writes_nothing() {
    let dir = tempfile::tempdir().unwrap();
    let log = dir.path().join("tank.csv");
    std::fs::write(&log, "timestamp,address,value\n0,%QX0.0,1\n1,%IX0.7,1\n").unwrap();
    let m = mapping();
    let reset = ResetActivity::parse("%IX0.1 false", &m).unwrap();
    let (xes_path, csv_path) = (dir.path().join("t.xes"), dir.path().join("t.csv"));
    let e = write_event_logs(&log, &m, &reset, false, &xes_path, &csv_path).unwrap_err();
    assert_eq!(
        e.to_string(),
        format!(
            "{}:3: unknown address '%IX0.7' (not in the mapping)",
            log.display()
        )
    );
    assert!(!xes_path.exists() && !csv_path.exists());
    assert_eq!(
        std::fs::read_dir(dir.path()).unwrap().count(),
        1,
        "no temporary file left"
    );
    // Lenient mode skips and counts the row.
    let s = write_event_logs(&log, &m, &reset, true, &xes_path, &csv_path).unwrap();
    assert_eq!((s.skipped, s.events), (1, 1));
}
