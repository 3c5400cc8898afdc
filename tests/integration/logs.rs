//! Plant-scale logs: Parquet input (written here with the `parquet` crate) and `synth batch`.

use crate::common::{nusmv_or_skip, synth, text, Dir};
use parquet::basic::{Compression, LogicalType, Repetition, Type as Physical};
use parquet::data_type::{BoolType, ByteArray, ByteArrayType, DoubleType, Int64Type};
use parquet::file::properties::WriterProperties;
use parquet::file::writer::SerializedFileWriter;
use parquet::schema::types::Type;
use std::path::Path;
use std::sync::Arc;

/// A column of a Parquet file: its name, physical type, whether it may hold nulls, and
/// whether its bytes are UTF-8 text.
fn field(name: &str, physical: Physical, optional: bool, text: bool) -> Arc<Type> {
    let repetition = if optional {
        Repetition::OPTIONAL
    } else {
        Repetition::REQUIRED
    };
    let mut b = Type::primitive_type_builder(name, physical).with_repetition(repetition);
    if text {
        b = b.with_logical_type(Some(LogicalType::String));
    }
    Arc::new(b.build().unwrap())
}

/// The values of one column in one row group; the levels of `Bools` are definition levels
/// (0: null) for an optional column.
enum Values {
    Bools(Vec<bool>, Option<Vec<i16>>),
    Longs(Vec<i64>),
    Doubles(Vec<f64>),
    Texts(Vec<String>),
}

/// Writes a Parquet file with the columns `fields` and one row group per entry of `groups`
/// (one [`Values`] per column each), compressed with `compression`.
fn write_parquet(
    file: &Path,
    fields: Vec<Arc<Type>>,
    compression: Compression,
    groups: Vec<Vec<Values>>,
) {
    let schema = Arc::new(
        Type::group_type_builder("log")
            .with_fields(fields)
            .build()
            .unwrap(),
    );
    let props = Arc::new(
        WriterProperties::builder()
            .set_compression(compression)
            .build(),
    );
    let out = std::fs::File::create(file).unwrap();
    let mut writer = SerializedFileWriter::new(out, schema, props).unwrap();
    for columns in groups {
        let mut group = writer.next_row_group().unwrap();
        for values in columns {
            let mut column = group.next_column().unwrap().unwrap();
            match values {
                Values::Bools(v, levels) => {
                    column
                        .typed::<BoolType>()
                        .write_batch(&v, levels.as_deref(), None)
                }
                Values::Longs(v) => column.typed::<Int64Type>().write_batch(&v, None, None),
                Values::Doubles(v) => column.typed::<DoubleType>().write_batch(&v, None, None),
                Values::Texts(v) => {
                    let v: Vec<ByteArray> = v.iter().map(|t| ByteArray::from(t.as_str())).collect();
                    column.typed::<ByteArrayType>().write_batch(&v, None, None)
                }
            }
            .unwrap();
            column.close().unwrap();
        }
        group.close().unwrap();
    }
    writer.close().unwrap();
}

/// Writes the CSV log `csv` (a header of `time`, `scenario` and signal columns, 0/1 cells) as a
/// Parquet file: `time` and `scenario` as INT64, the signals as BOOLEAN, snappy-compressed as
/// Spark writes by default.
fn csv_to_parquet(csv: &Path, out: &Path) {
    let text = std::fs::read_to_string(csv).unwrap();
    let mut lines = text.lines();
    let header: Vec<&str> = lines.next().unwrap().split(',').collect();
    let rows: Vec<Vec<i64>> = lines
        .filter(|l| !l.trim().is_empty())
        .map(|l| l.split(',').map(|c| c.trim().parse().unwrap()).collect())
        .collect();
    let numeric = |name: &str| name == "time" || name == "scenario";
    let fields = header
        .iter()
        .map(|&name| {
            let physical = if numeric(name) {
                Physical::INT64
            } else {
                Physical::BOOLEAN
            };
            field(name, physical, false, false)
        })
        .collect();
    // Two row groups, as a writer flushing by size would make.
    let groups = rows
        .chunks(rows.len().div_ceil(2))
        .map(|part| {
            (0..header.len())
                .map(|k| {
                    let values: Vec<i64> = part.iter().map(|r| r[k]).collect();
                    if numeric(header[k]) {
                        Values::Longs(values)
                    } else {
                        Values::Bools(values.iter().map(|&v| v != 0).collect(), None)
                    }
                })
                .collect()
        })
        .collect();
    write_parquet(out, fields, Compression::SNAPPY, groups);
}

#[test]
fn a_parquet_log_gives_the_machine_of_the_same_csv_log() {
    let dir = Dir::new();
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let parquet = dir.path().join("distribution.parquet");
    csv_to_parquet(&root.join("specs/distribution.csv"), &parquet);
    let infer = |traces: &str, out: &Path| {
        let o = synth(&[
            "infer",
            "-q",
            "--no-ambiguity",
            "--traces",
            traces,
            "--out",
            out.to_str().unwrap(),
            "--format",
            "json",
        ]);
        assert!(o.status.success(), "{traces}: {}", text(&o.stderr));
        (
            text(&o.stdout).lines().next().unwrap().to_string(),
            std::fs::read_to_string(out.join("SynthesizedFB.json")).unwrap(),
        )
    };
    let from_csv = infer("specs/distribution.csv", &dir.path().join("csv"));
    let from_parquet = infer(parquet.to_str().unwrap(), &dir.path().join("parquet"));
    assert!(from_csv.0.starts_with("C = 9"), "{}", from_csv.0);
    assert_eq!(from_csv, from_parquet);

    // A partitioned folder (`plc=1/part-0.parquet`) reads like the file.
    let part = dir.path().join("lake/plc=1");
    std::fs::create_dir_all(&part).unwrap();
    std::fs::copy(&parquet, part.join("part-0.parquet")).unwrap();
    std::fs::write(part.join("_SUCCESS"), "").unwrap();
    let from_folder = infer(
        dir.path().join("lake").to_str().unwrap(),
        &dir.path().join("folder"),
    );
    assert_eq!(from_csv, from_folder);

    // Not Parquet: refused with the file named.
    let fake = dir.path().join("fake.parquet");
    std::fs::write(&fake, "time,scenario\n").unwrap();
    let o = synth(&["infer", "--traces", fake.to_str().unwrap(), "--out", "-"]);
    assert_eq!(o.status.code(), Some(4));
    assert!(
        text(&o.stderr).contains("fake.parquet:1: not a readable Parquet file"),
        "{}",
        text(&o.stderr)
    );
}

#[test]
fn batch_writes_a_folder_per_plc_and_a_summary_table() {
    let dir = Dir::new();
    let logs = dir.path().join("logs");
    std::fs::create_dir_all(logs.join("plc=dist")).unwrap();
    // The case simulations' recordings, one PLC each: CSV logs, and a Parquet partition.
    for case in ["pnp", "tank1", "tank2"] {
        let o = synth(&[
            "convert",
            "--traces",
            &format!("specs/{case}.traces"),
            "--to",
            "csv",
            "--output",
            logs.join(format!("{case}.csv")).to_str().unwrap(),
        ]);
        assert!(o.status.success(), "{}", text(&o.stderr));
    }
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    csv_to_parquet(
        &root.join("specs/distribution.csv"),
        &logs.join("plc=dist/part-00000.parquet"),
    );
    std::fs::write(logs.join("notes.txt"), "not a log\n").unwrap();
    let out = dir.path().join("out");
    let o = synth(&[
        "batch",
        "--logs",
        logs.to_str().unwrap(),
        "--out",
        out.to_str().unwrap(),
        "--format",
        "json,st",
        "--json",
    ]);
    assert!(o.status.success(), "{}", text(&o.stderr));
    let summary: serde_json::Value = serde_json::from_slice(&o.stdout).unwrap();
    let rows = summary["plcs"].as_array().unwrap();
    let size = |plc: &str| {
        let r = rows.iter().find(|r| r["plc"] == plc).unwrap();
        assert_eq!(r["status"], "ok", "{r}");
        ["C", "T", "N"].map(|k| r[k].as_u64().unwrap())
    };
    // The sizes `synth infer` finds on the same logs.
    assert_eq!(rows.len(), 4);
    for (plc, source) in [
        ("pnp", logs.join("pnp.csv")),
        ("tank1", logs.join("tank1.csv")),
        ("tank2", logs.join("tank2.csv")),
        ("plc=dist", logs.join("plc=dist")),
    ] {
        let o = synth(&[
            "infer",
            "-q",
            "--no-ambiguity",
            "--traces",
            source.to_str().unwrap(),
            "--out",
            "-",
        ]);
        assert!(o.status.success(), "{}", text(&o.stderr));
        let ecc: serde_json::Value = serde_json::from_slice(&o.stdout).unwrap();
        let states = ecc["states"].as_array().unwrap().len() as u64;
        let transitions = ecc["transitions"].as_array().unwrap().len() as u64;
        let [c, t, _] = size(plc);
        assert_eq!((c, t), (states, transitions), "{plc}");
    }
    assert_eq!(size("plc=dist"), [9, 13, 13]);
    let csv = std::fs::read_to_string(out.join("summary.csv")).unwrap();
    assert!(csv.starts_with("plc,source,status,scenarios,steps,C,K,T,N,seconds,message\n"));
    assert_eq!(csv.lines().count(), 5, "{csv}");
    for (plc, log) in [
        ("pnp", logs.join("pnp.csv")),
        ("tank1", logs.join("tank1.csv")),
        ("plc=dist", root.join("specs/distribution.csv")),
    ] {
        let file = out.join(plc).join("SynthesizedFB.json");
        let ecc = fbsynth::export::json::read_json(&std::fs::read_to_string(&file).unwrap(), &file)
            .unwrap();
        let set = fbsynth::scenario::csvlog::read(&log, None, None).unwrap();
        set.check(&ecc).unwrap();
        assert!(out.join(plc).join("SynthesizedFB.st").is_file());
    }

    // A PLC whose log is broken fails alone: the others are written, the summary says why,
    // and the exit code is 1.
    std::fs::write(logs.join("broken.csv"), "time,in:a,out:b\n0,1,maybe\n").unwrap();
    let out2 = dir.path().join("out2");
    let o = synth(&[
        "batch",
        "-q",
        "--logs",
        logs.to_str().unwrap(),
        "--out",
        out2.to_str().unwrap(),
    ]);
    assert_eq!(o.status.code(), Some(4), "{}", text(&o.stderr));
    assert!(
        text(&o.stderr).contains("1 of 5 PLCs have no machine: broken"),
        "{}",
        text(&o.stderr)
    );
    let csv = std::fs::read_to_string(out2.join("summary.csv")).unwrap();
    let broken = csv.lines().find(|l| l.starts_with("broken,")).unwrap();
    assert!(
        broken.contains(",failed,") && broken.contains("broken.csv:2"),
        "{broken}"
    );
    assert!(out2.join("pnp/SynthesizedFB.json").is_file());
    assert!(!out2.join("broken").exists());
}

#[test]
fn ingest_reads_a_parquet_data_flow_log_as_its_csv() {
    let dir = Dir::new();
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let csv = std::fs::read_to_string(root.join("specs/tank/scenario1.csv")).unwrap();
    let rows: Vec<(f64, String, i64)> = csv
        .lines()
        .skip(1)
        .filter(|l| !l.trim().is_empty())
        .map(|l| {
            let c: Vec<&str> = l.split(',').collect();
            (
                c[0].parse().unwrap(),
                c[1].to_string(),
                c[2].trim().parse().unwrap(),
            )
        })
        .collect();
    let parquet = dir.path().join("scenario1.parquet");
    write_parquet(
        &parquet,
        vec![
            field("timestamp", Physical::DOUBLE, false, false),
            field("address", Physical::BYTE_ARRAY, false, true),
            field("value", Physical::INT64, false, false),
        ],
        Compression::UNCOMPRESSED,
        vec![vec![
            Values::Doubles(rows.iter().map(|r| r.0).collect()),
            Values::Texts(rows.iter().map(|r| r.1.clone()).collect()),
            Values::Longs(rows.iter().map(|r| r.2).collect()),
        ]],
    );

    let ingest = |log: &Path, out: &Path| {
        let o = synth(&[
            "ingest",
            "--log",
            log.to_str().unwrap(),
            "--map",
            "specs/tank/tank.map",
            "-o",
            out.to_str().unwrap(),
        ]);
        assert!(o.status.success(), "{}", text(&o.stderr));
        std::fs::read_to_string(out).unwrap()
    };
    let from_csv = ingest(
        &root.join("specs/tank/scenario1.csv"),
        &dir.path().join("csv.traces"),
    );
    let from_parquet = ingest(&parquet, &dir.path().join("parquet.traces"));
    assert!(from_csv.starts_with("1\nin=REQ["), "{from_csv}");
    assert_eq!(from_csv, from_parquet);
}

#[test]
fn batch_with_properties_verifies_every_machine_with_nusmv() {
    let Some(n) = nusmv_or_skip() else {
        return;
    };
    let dir = Dir::new();
    let logs = dir.path().join("logs");
    std::fs::create_dir_all(&logs).unwrap();
    for plc in ["hall", "stairs"] {
        let o = synth(&[
            "convert",
            "--traces",
            "tests/data/closed_loop/lamp.traces",
            "--to",
            "csv",
            "--output",
            logs.join(format!("{plc}.csv")).to_str().unwrap(),
        ]);
        assert!(o.status.success(), "{}", text(&o.stderr));
    }
    let out = dir.path().join("out");
    let o = synth(&[
        "batch",
        "-q",
        "--logs",
        logs.to_str().unwrap(),
        "--ltl",
        "tests/data/closed_loop/lamp.ltl",
        "--plant",
        "tests/data/closed_loop/lamp_plant.smv",
        "--nusmv",
        n.path.to_str().unwrap(),
        "--out",
        out.to_str().unwrap(),
    ]);
    assert!(o.status.success(), "{}", text(&o.stderr));
    let csv = std::fs::read_to_string(out.join("summary.csv")).unwrap();
    for plc in ["hall", "stairs"] {
        let row = csv
            .lines()
            .find(|l| l.starts_with(&format!("{plc},")))
            .unwrap();
        assert!(row.contains(",verified,"), "{row}");
        let report = std::fs::read_to_string(out.join(plc).join("verification.txt")).unwrap();
        assert!(report.contains("HOLDS"), "{report}");
        // NuSMV agrees on the machine written.
        let v = synth(&[
            "verify",
            "--ecc",
            out.join(plc).join("SynthesizedFB.json").to_str().unwrap(),
            "--ltl",
            "tests/data/closed_loop/lamp.ltl",
            "--plant",
            "tests/data/closed_loop/lamp_plant.smv",
            "--nusmv",
            n.path.to_str().unwrap(),
        ]);
        assert!(v.status.success(), "{}", text(&v.stderr));
    }
}

#[test]
fn a_null_in_a_parquet_log_is_refused_at_its_row() {
    let dir = Dir::new();
    let file = dir.path().join("gap.parquet");
    // Rows 1 and 3 have a value of `out:z`, row 2 none (definition level 0).
    write_parquet(
        &file,
        vec![
            field("in:a", Physical::BOOLEAN, false, false),
            field("out:z", Physical::BOOLEAN, true, false),
        ],
        Compression::UNCOMPRESSED,
        vec![vec![
            Values::Bools(vec![false, true, true], None),
            Values::Bools(vec![false, true], Some(vec![1, 0, 1])),
        ]],
    );
    let out = dir.path().join("out");
    let o = synth(&[
        "infer",
        "--traces",
        file.to_str().unwrap(),
        "--out",
        out.to_str().unwrap(),
    ]);
    assert_eq!(o.status.code(), Some(4), "{}", text(&o.stderr));
    // Row 2 is line 3 of the CSV log it stands for.
    assert!(
        text(&o.stderr).contains("gap.parquet:3: column 2 ('out:z')"),
        "{}",
        text(&o.stderr)
    );
    assert!(!out.exists());
}

/// One long run is synthesized a part at a time: the first part is encoded, the whole run is
/// replayed, and the machine written reproduces every recorded step (`synth replay`).
#[test]
fn a_long_run_is_synthesized_in_parts_and_the_machine_replays_all_of_it() {
    let dir = Dir::new();
    let set = crate::cases::distribution::long_run(12_000, 5);
    let traces = dir.path().join("long.traces");
    let mut bytes = Vec::new();
    fbsynth::scenario::fbsat::write(&set, &mut bytes).unwrap();
    std::fs::write(&traces, bytes).unwrap();
    let (inputs, outputs) = (dir.path().join("in.names"), dir.path().join("out.names"));
    std::fs::write(&inputs, set.inputs.join("\n")).unwrap();
    std::fs::write(&outputs, set.outputs.join("\n")).unwrap();
    let out = dir.path().join("out");
    let names = [
        "--input-names",
        inputs.to_str().unwrap(),
        "--output-names",
        outputs.to_str().unwrap(),
    ];
    let mut args = vec!["infer", "--traces", traces.to_str().unwrap()];
    args.extend(names);
    args.extend(["--out", out.to_str().unwrap()]);
    let o = synth(&args);
    assert!(o.status.success(), "{}", text(&o.stderr));
    let err = text(&o.stderr);
    assert!(
        err.contains("of 12000 recorded steps encoded; the machine reproduces every step"),
        "{err}"
    );
    let json = out.join("SynthesizedFB.json");
    let mut args = vec!["replay", "--ecc", json.to_str().unwrap()];
    args.extend(["--traces", traces.to_str().unwrap()]);
    args.extend(names);
    let o = synth(&args);
    assert!(o.status.success(), "{}", text(&o.stderr));
    assert!(text(&o.stdout).starts_with("replayed 1 scenarios (12000 steps): all reproduced"));
}
