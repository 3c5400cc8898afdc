//! Plant-scale logs: Parquet input (written here with the `parquet` crate) and `synth batch`.

use parquet::basic::{Compression, Repetition, Type as Physical};
use parquet::data_type::{BoolType, Int64Type};
use parquet::file::properties::WriterProperties;
use parquet::file::writer::SerializedFileWriter;
use parquet::schema::types::Type;
use std::path::Path;
use std::process::{Command, Output};
use std::sync::Arc;

fn synth(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_synth"))
        .args(args)
        .current_dir(env!("CARGO_MANIFEST_DIR"))
        .output()
        .expect("run synth")
}

fn text(b: &[u8]) -> String {
    String::from_utf8_lossy(b).into_owned()
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
            Arc::new(
                Type::primitive_type_builder(name, physical)
                    .with_repetition(Repetition::REQUIRED)
                    .build()
                    .unwrap(),
            )
        })
        .collect();
    let schema = Arc::new(
        Type::group_type_builder("log")
            .with_fields(fields)
            .build()
            .unwrap(),
    );
    let props = Arc::new(
        WriterProperties::builder()
            .set_compression(Compression::SNAPPY)
            .build(),
    );
    let file = std::fs::File::create(out).unwrap();
    let mut writer = SerializedFileWriter::new(file, schema, props).unwrap();
    // Two row groups, as a writer flushing by size would make.
    for part in rows.chunks(rows.len().div_ceil(2)) {
        let mut group = writer.next_row_group().unwrap();
        let mut k = 0;
        while let Some(mut column) = group.next_column().unwrap() {
            let values: Vec<i64> = part.iter().map(|r| r[k]).collect();
            if numeric(header[k]) {
                column
                    .typed::<Int64Type>()
                    .write_batch(&values, None, None)
                    .unwrap();
            } else {
                let bits: Vec<bool> = values.iter().map(|&v| v != 0).collect();
                column
                    .typed::<BoolType>()
                    .write_batch(&bits, None, None)
                    .unwrap();
            }
            column.close().unwrap();
            k += 1;
        }
        group.close().unwrap();
    }
    writer.close().unwrap();
}

#[test]
fn a_parquet_log_gives_the_machine_of_the_same_csv_log() {
    let dir = tempfile::tempdir().unwrap();
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
    assert_eq!(o.status.code(), Some(1));
    assert!(
        text(&o.stderr).contains("fake.parquet:1: not a readable Parquet file"),
        "{}",
        text(&o.stderr)
    );
}
