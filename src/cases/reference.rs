//! The reference controllers of the cases: the hand-made "legacy PLC" programs whose logic
//! synthesis recovers, written as tables, with their interfaces.
//!
//! In: nothing but the tables. Out: each controller as an [`Ecc`]. They are always part of the
//! library, unlike the plant simulations beside them: `synth learn --oracle case:NAME` asks
//! them ([`named`]).

use crate::ecc::{Algorithm, Ecc, State, StateId, Transition, Tri};
use crate::export::guard_text::parse_guard;

/// The names `synth learn --oracle case:NAME` takes, in the order [`named`] lists them.
pub const NAMES: [&str; 4] = ["pnp", "distribution", "tank1", "tank2"];

/// The reference controller of the case called `name` ([`NAMES`]).
pub fn named(name: &str) -> Option<Ecc> {
    match name {
        "pnp" => Some(pnp::reference()),
        "distribution" => Some(distribution::reference()),
        "tank1" => Some(tank::fill_drain()),
        "tank2" => Some(tank::cycles()),
        _ => None,
    }
}

/// The Pick-and-Place manipulator (`super::pnp`).
pub mod pnp {
    use crate::ecc::Ecc;

    /// Controller inputs (plant sensors), in interface order.
    pub const INPUTS: [&str; 10] = [
        "c1Home", "c1End", "c2Home", "c2End", "vcHome", "vcEnd", "pp1", "pp2", "pp3", "vac",
    ];

    /// Controller outputs (plant commands), in interface order.
    pub const OUTPUTS: [&str; 7] = [
        "c1Extend",
        "c1Retract",
        "c2Extend",
        "c2Retract",
        "vcExtend",
        "vacuum_on",
        "vacuum_off",
    ];

    /// Input names in interface order.
    pub fn input_names() -> Vec<String> {
        INPUTS.iter().map(|s| s.to_string()).collect()
    }

    /// Output names in interface order.
    pub fn output_names() -> Vec<String> {
        OUTPUTS.iter().map(|s| s.to_string()).collect()
    }

    // The reference controller as tables. Algorithms list one symbol per output in OUTPUTS order:
    //                          c1Extend c1Retract c2Extend c2Retract vcExtend vacuum_on vacuum_off
    const STATES: [(&str, &str); 11] = [
        ("Idle", "0000000"),       // waiting for a piece, everything off
        ("ToTrack2", "1000000"),   // cylinder I out: hand over track 2
        ("ToTrack3", "0010000"),   // cylinder II out: hand over track 3
        ("Down", "0000100"),       // lower the cup onto the piece
        ("Suck", "0000110"),       // keep down, suction on
        ("Lift", "0000000"),       // release vcExtend: the spring lifts the piece
        ("ToSlider", "1010000"),   // both horizontal cylinders out: over the slider
        ("DownSlider", "0000100"), // lower the piece onto the slider
        ("Release", "0000101"),    // keep down, suction off
        ("Up", "0000000"),         // back up
        ("Return", "0101000"),     // both horizontal cylinders in: home over track 1
    ];

    // (from, to, guard) in priority order per state. Idle serves track 1 before 2 before 3.
    const TRANSITIONS: [(&str, &str, &str); 13] = [
        ("Idle", "Down", "pp1"),
        ("Idle", "ToTrack2", "pp2"),
        ("Idle", "ToTrack3", "pp3"),
        ("ToTrack2", "Down", "c1End"),
        ("ToTrack3", "Down", "c2End"),
        ("Down", "Suck", "vcEnd"),
        ("Suck", "Lift", "vac"),
        ("Lift", "ToSlider", "vcHome"),
        ("ToSlider", "DownSlider", "c1End & c2End"),
        ("DownSlider", "Release", "vcEnd"),
        ("Release", "Up", "!vac"),
        ("Up", "Return", "vcHome"),
        ("Return", "Idle", "c1Home & c2Home"),
    ];

    /// The hand-made reference controller: 11 states, state 0 (`Idle`) initial, all outputs 0
    /// initially. One cycle: move over the track of a waiting piece (priority 1 > 2 > 3), go down,
    /// suck, go up, move over the output slider, go down, release, go up, return home.
    ///
    /// By construction it never commands extend and retract of one cylinder together, never
    /// `vacuum_on` with `vacuum_off`, and commands horizontal moves only in states entered with the
    /// vertical cylinder up and not commanded down.
    pub fn reference() -> Ecc {
        super::table_ecc(&INPUTS, &OUTPUTS, &STATES, &TRANSITIONS)
    }
}

/// The distribution station (`super::distribution`).
pub mod distribution {
    use crate::ecc::Ecc;

    /// Controller inputs (sensors and HMI), in interface order.
    pub const INPUTS: [&str; 10] = [
        "empty",
        "retracted",
        "extended",
        "at_magazine",
        "at_client",
        "vac_on",
        "start",
        "stop",
        "auto_man",
        "emergency",
    ];

    /// Controller outputs (commands and lamps), in interface order.
    pub const OUTPUTS: [&str; 7] = [
        "retract",
        "vacuum_on",
        "vacuum_off",
        "to_magazine",
        "to_client",
        "start_led",
        "reset_led",
    ];

    /// States of the reference controller: name and algorithm (one symbol per output).
    const STATES: [(&str, &str); 9] = [
        ("Idle", "0000000"),
        ("Ready", "0000010"),
        ("Retract", "1000010"),
        ("Push", "0000010"),
        ("Suck", "0100010"),
        ("ToClient", "0000110"),
        ("Release", "0010010"),
        ("ToMagazine", "0001010"),
        ("EmergencyStop", "0000001"),
    ];

    /// Transitions in priority order per source state: (from, to, guard).
    const TRANSITIONS: [(&str, &str, &str); 19] = [
        ("Idle", "EmergencyStop", "emergency"),
        ("Idle", "Ready", "start & !stop"),
        ("Ready", "EmergencyStop", "emergency"),
        ("Ready", "Idle", "stop"),
        ("Ready", "Retract", "!start & auto_man & !empty"),
        ("Retract", "EmergencyStop", "emergency"),
        ("Retract", "Push", "retracted"),
        ("Push", "EmergencyStop", "emergency"),
        ("Push", "Suck", "extended & at_magazine"),
        ("Suck", "EmergencyStop", "emergency"),
        ("Suck", "ToClient", "vac_on"),
        ("ToClient", "Release", "at_client"),
        ("Release", "EmergencyStop", "emergency"),
        ("Release", "ToMagazine", "!vac_on"),
        ("ToMagazine", "EmergencyStop", "emergency"),
        ("ToMagazine", "Retract", "at_magazine & auto_man & !empty"),
        ("ToMagazine", "Ready", "at_magazine"),
        ("EmergencyStop", "Idle", "!emergency & stop"),
        ("ToClient", "EmergencyStop", "emergency"),
    ];

    /// Input names in interface order.
    pub fn input_names() -> Vec<String> {
        INPUTS.iter().map(|s| s.to_string()).collect()
    }

    /// Output names in interface order.
    pub fn output_names() -> Vec<String> {
        OUTPUTS.iter().map(|s| s.to_string()).collect()
    }

    /// The hand-made reference controller ("the legacy PLC"): 9 states, state 0 (`Idle`)
    /// initial, all outputs 0 initially. In automatic mode it takes pieces from the magazine to the
    /// client one by one while the magazine is not empty; `stop` in `Ready` goes back to `Idle`;
    /// `emergency` stops every motion (lamp `reset_led`) until `stop` acknowledges it.
    pub fn reference() -> Ecc {
        // Emergency first in every state: the priority order is what makes it win. The sort is
        // stable, so the other transitions keep their table order.
        let mut ordered = TRANSITIONS.to_vec();
        ordered.sort_by_key(|(_, to, _)| *to != "EmergencyStop");
        super::table_ecc(&INPUTS, &OUTPUTS, &STATES, &ordered)
    }
}

/// The tank level control (`super::tank`): its two programs.
pub mod tank {
    use crate::ecc::Ecc;

    /// Controller inputs (level sensors), in interface order.
    pub const INPUTS: [&str; 3] = ["ll", "ml", "ul"];
    /// Controller outputs (valves), in interface order.
    pub const OUTPUTS: [&str; 2] = ["inlet", "outlet"];
    /// Program 2's number of middle-to-upper cycles.
    pub const CYCLES: usize = 3;

    // Algorithms are `inlet outlet`.
    const P1_STATES: [(&str, &str); 2] = [("Drain", "01"), ("Fill", "10")];
    const P1_TRANSITIONS: [(&str, &str, &str); 2] =
        [("Drain", "Fill", "!ll"), ("Fill", "Drain", "ul")];

    const P2_STATES: [(&str, &str); 2 + 2 * CYCLES] = [
        ("Drain", "01"),
        ("Fill", "10"),
        ("Lower1", "01"),
        ("Raise1", "10"),
        ("Lower2", "01"),
        ("Raise2", "10"),
        ("Lower3", "01"),
        ("Raise3", "10"),
    ];
    const P2_TRANSITIONS: [(&str, &str, &str); 2 + 2 * CYCLES] = [
        ("Drain", "Fill", "!ll"),
        ("Fill", "Lower1", "ul"),
        ("Lower1", "Raise1", "!ml"),
        ("Raise1", "Lower2", "ul"),
        ("Lower2", "Raise2", "!ml"),
        ("Raise2", "Lower3", "ul"),
        ("Lower3", "Raise3", "!ml"),
        ("Raise3", "Drain", "ul"),
    ];

    /// Program 1: fill to `ul`, drain to `ll`; state 0 (`Drain`) initial, valves closed initially.
    pub fn fill_drain() -> Ecc {
        super::table_ecc(&INPUTS, &OUTPUTS, &P1_STATES, &P1_TRANSITIONS)
    }

    /// Program 2: fill to `ul`, [`CYCLES`] times down to `ml` and up to `ul`, drain to `ll`;
    /// state 0 (`Drain`) initial, valves closed initially.
    pub fn cycles() -> Ecc {
        super::table_ecc(&INPUTS, &OUTPUTS, &P2_STATES, &P2_TRANSITIONS)
    }
}

/// A reference controller written as tables: states `(name, algorithm)` with the algorithm as
/// `0/1/x` symbols per output, and transitions `(from, to, guard text)` in priority order.
/// State 0 is initial, every output starts 0. The tables are constants of a case module, so a
/// bad name or guard there is a bug and panics.
pub(crate) fn table_ecc(
    inputs: &[&str],
    outputs: &[&str],
    states: &[(&str, &str)],
    transitions: &[(&str, &str, &str)],
) -> Ecc {
    let id = |name: &str| {
        StateId(
            states
                .iter()
                .position(|(n, _)| *n == name)
                .unwrap_or_else(|| panic!("unknown state '{name}'")),
        )
    };
    let inputs: Vec<String> = inputs.iter().map(|s| s.to_string()).collect();
    let states = states
        .iter()
        .map(|(name, algorithm)| State {
            name: name.to_string(),
            algorithm: Algorithm::Tri(
                algorithm
                    .chars()
                    .map(|c| Tri::from_symbol(c).expect("algorithm symbol"))
                    .collect(),
            ),
            transitions: transitions
                .iter()
                .filter(|(from, _, _)| from == name)
                .map(|(_, to, guard)| Transition {
                    target: id(to),
                    guard: parse_guard(guard, &inputs)
                        .unwrap_or_else(|e| panic!("guard '{guard}': {e}")),
                })
                .collect(),
        })
        .collect();
    Ecc {
        inputs,
        outputs: outputs.iter().map(|s| s.to_string()).collect(),
        initial_outputs: vec![false; outputs.len()],
        states,
    }
}
