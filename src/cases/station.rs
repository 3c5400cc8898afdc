//! A station of the project's own, drawn at random from a seed: 3 or 4 single-acting
//! cylinders with end sensors, 2 or 3 latching request buttons, each request a sequence of 2
//! or 3 cylinder strokes (out to the end sensor, back home), a reference controller, its plant
//! as SMV, properties of exclusion, reaching, returning and service, and one recorded run of
//! [`STEPS`] scans. The run serves the requests pressed first; later ones are pressed but
//! rarely served within it: every value the properties read is recorded, whole behaviours
//! are not.
//!
//! In: a seed. Out: a [`Station`] (its shape and reference controller) and, with
//! [`write_files`], `plant.smv`, `station.ltl`, `station.traces`, `station.inputs` and
//! `station.outputs` in a folder, read by `synth --ltl station.ltl --plant plant.smv`.
//!
//! # The plant (one step is one scan)
//! Cylinder `k` has a position `0..2` (home, between, end): it moves one unit a scan towards
//! the end while its valve `c{k}ext` is on, towards home while it is off; `c{k}home` and
//! `c{k}end` are its sensors. Button `b{j}` (free: the operator) latches request `r{j}`, which
//! the controller's acknowledgement `ack{j}` clears (a press in the same scan wins).

use crate::ecc::{Algorithm, Ecc, Guard, InputId, Run, State, StateId, Transition, Tri};
use crate::files::{write_atomic, WriteError};
use std::path::{Path, PathBuf};

/// Scans of the recorded run.
pub const STEPS: usize = 40;

/// A station: its cylinders and its requests' strokes.
#[derive(Debug, Clone)]
pub struct Station {
    /// Number of cylinders.
    pub cylinders: usize,
    /// Per request: the cylinders it strokes, in order.
    pub requests: Vec<Vec<usize>>,
    /// Per scan of the recorded run: the buttons pressed.
    presses: Vec<Vec<bool>>,
}

/// A pseudo-random generator (linear congruential), so that a seed gives the same station on
/// every machine.
struct Lcg(u64);

impl Lcg {
    fn below(&mut self, n: usize) -> usize {
        self.0 = (self.0)
            .wrapping_mul(6_364_136_223_846_793_005)
            .wrapping_add(1_442_695_040_888_963_407);
        ((self.0 >> 33) % n as u64) as usize
    }
}

impl Station {
    /// The station of `seed`.
    pub fn generate(seed: u64) -> Station {
        let mut rng = Lcg(seed ^ 0x9e37_79b9_7f4a_7c15);
        let cylinders = 3 + rng.below(2);
        let requests = (0..2 + rng.below(2))
            .map(|_| {
                let mut strokes: Vec<usize> = Vec::new();
                for _ in 0..2 + rng.below(2) {
                    // Two strokes in a row move different cylinders.
                    let mut c = rng.below(cylinders);
                    while strokes.last() == Some(&c) {
                        c = rng.below(cylinders);
                    }
                    strokes.push(c);
                }
                strokes
            })
            .collect::<Vec<_>>();
        // The first request is pressed at once, the others once each, later in the run.
        let pressed_at: Vec<usize> = std::iter::once(1)
            .chain((1..requests.len()).map(|_| 4 + rng.below(STEPS - 8)))
            .collect();
        let presses = (0..STEPS)
            .map(|t| pressed_at.iter().map(|&at| at == t).collect())
            .collect();
        Station {
            cylinders,
            requests,
            presses,
        }
    }

    /// Controller inputs: `r{j}` per request, then `c{k}home`, `c{k}end` per cylinder.
    pub fn inputs(&self) -> Vec<String> {
        let mut names: Vec<String> = (1..=self.requests.len()).map(|j| format!("r{j}")).collect();
        for k in 1..=self.cylinders {
            names.push(format!("c{k}home"));
            names.push(format!("c{k}end"));
        }
        names
    }

    /// Controller outputs: `c{k}ext` per cylinder, then `ack{j}` per request.
    pub fn outputs(&self) -> Vec<String> {
        let mut names: Vec<String> = (1..=self.cylinders).map(|k| format!("c{k}ext")).collect();
        names.extend((1..=self.requests.len()).map(|j| format!("ack{j}")));
        names
    }

    /// The reference controller: an idle state that starts the first pending request (request
    /// 1 first), and per stroke a state that extends the cylinder until its end sensor and one
    /// that retracts it until home; the first stroke's extending state acknowledges the
    /// request.
    pub fn reference(&self) -> Ecc {
        let (c, m) = (self.cylinders, self.requests.len());
        let input = |name: String| {
            Guard::Var(InputId(
                self.inputs()
                    .iter()
                    .position(|n| *n == name)
                    .expect("an input of the station"),
            ))
        };
        let algorithm = |ext: Option<usize>, ack: Option<usize>| {
            let mut a = vec![Tri::Zero; c + m];
            if let Some(k) = ext {
                a[k] = Tri::One;
            }
            if let Some(j) = ack {
                a[c + j] = Tri::One;
            }
            Algorithm::Tri(a)
        };
        let mut states = vec![State {
            name: "idle".into(),
            algorithm: algorithm(None, None),
            transitions: Vec::new(),
        }];
        for (j, strokes) in self.requests.iter().enumerate() {
            let first = states.len();
            states[0].transitions.push(Transition {
                target: StateId(first),
                guard: input(format!("r{}", j + 1)),
            });
            for (s, &k) in strokes.iter().enumerate() {
                let out = states.len();
                let back = out + 1;
                let next = if s + 1 == strokes.len() { 0 } else { back + 1 };
                states.push(State {
                    name: format!("r{}_out{}", j + 1, s + 1),
                    algorithm: algorithm(Some(k), (s == 0).then_some(j)),
                    transitions: vec![Transition {
                        target: StateId(back),
                        guard: input(format!("c{}end", k + 1)),
                    }],
                });
                states.push(State {
                    name: format!("r{}_back{}", j + 1, s + 1),
                    algorithm: algorithm(None, None),
                    transitions: vec![Transition {
                        target: StateId(next),
                        guard: input(format!("c{}home", k + 1)),
                    }],
                });
            }
        }
        Ecc {
            inputs: self.inputs(),
            outputs: self.outputs(),
            initial_outputs: vec![false; c + m],
            states,
        }
    }

    /// The plant model (module documentation), its parameters the controller's outputs.
    pub fn plant(&self) -> String {
        let (c, m) = (self.cylinders, self.requests.len());
        let mut t = format!(
            "-- A station of {c} cylinders and {m} latching requests: generated by fbsynth::cases::station.\n\
             MODULE plant({})\nVAR\n",
            self.outputs().join(", ")
        );
        for k in 1..=c {
            t.push_str(&format!("    p{k} : 0..2;\n"));
        }
        for j in 1..=m {
            t.push_str(&format!("    b{j} : boolean;\n    r{j} : boolean;\n"));
        }
        t.push_str("ASSIGN\n");
        for k in 1..=c {
            t.push_str(&format!(
                "    init(p{k}) := 0;\n    next(p{k}) := case\n        c{k}ext & p{k} < 2 : p{k} + 1;\n        !c{k}ext & p{k} > 0 : p{k} - 1;\n        TRUE : p{k};\n    esac;\n"
            ));
        }
        for j in 1..=m {
            t.push_str(&format!(
                "    init(r{j}) := FALSE;\n    next(r{j}) := case\n        b{j} : TRUE;\n        ack{j} : FALSE;\n        TRUE : r{j};\n    esac;\n"
            ));
        }
        t.push_str("DEFINE\n");
        for k in 1..=c {
            t.push_str(&format!(
                "    c{k}home := p{k} = 0;\n    c{k}end := p{k} = 2;\n"
            ));
        }
        t
    }

    /// The properties: no two cylinders out at once; a cylinder sent out stays sent until its
    /// end sensor; every cylinder at its end comes home; every request is acknowledged, the
    /// later ones once the operator stops pressing the earlier ones' buttons (the reference
    /// serves request 1 first).
    pub fn properties(&self) -> String {
        let (c, m) = (self.cylinders, self.requests.len());
        let mut pairs = Vec::new();
        for a in 1..=c {
            for b in a + 1..=c {
                pairs.push(format!("(c{a}ext & c{b}ext)"));
            }
        }
        let mut t = format!(
            "-- Properties of a generated station (fbsynth::cases::station).\n\
             exclusion: G !({})\n",
            pairs.join(" | ")
        );
        for k in 1..=c {
            t.push_str(&format!(
                "reaching{k}: G (c{k}ext -> (c{k}ext U c{k}end))\n"
            ));
            t.push_str(&format!("returning{k}: G (c{k}end -> F c{k}home)\n"));
        }
        for j in 1..=m {
            let earlier: Vec<String> = (1..j).map(|i| format!("b{i}")).collect();
            match earlier.is_empty() {
                true => t.push_str(&format!("service{j}: G (r{j} -> F ack{j})\n")),
                false => t.push_str(&format!(
                    "service{j}: (F G !({})) -> G (r{j} -> F ack{j})\n",
                    earlier.join(" | ")
                )),
            }
        }
        t
    }

    /// The recorded run: [`STEPS`] scans of the reference controller in closed loop with the
    /// plant, the buttons pressed as drawn, in the scenario file format.
    pub fn traces(&self) -> String {
        let (c, m) = (self.cylinders, self.requests.len());
        let ecc = self.reference();
        let mut run = Run::new(&ecc);
        let mut pos = vec![0u8; c];
        let mut req = vec![false; m];
        let bits = |v: &[bool]| {
            v.iter()
                .map(|&b| if b { '1' } else { '0' })
                .collect::<String>()
        };
        let mut events = Vec::new();
        for press in &self.presses {
            let mut x = req.clone();
            for &p in &pos {
                x.push(p == 0);
                x.push(p == 2);
            }
            let before = run.outputs.clone();
            events.push(format!("in=REQ[{}];", bits(&x)));
            if run.step(&x).is_some() {
                events.push(format!("out=CNF[{}];", bits(&run.outputs)));
            }
            // The plant's step reads the outputs of the scan before the controller's answer.
            for (k, p) in pos.iter_mut().enumerate() {
                match before[k] {
                    true if *p < 2 => *p += 1,
                    false if *p > 0 => *p -= 1,
                    _ => {}
                }
            }
            for (j, r) in req.iter_mut().enumerate() {
                *r = press[j] || (*r && !before[c + j]);
            }
        }
        format!("1\n{}\n", events.join(" "))
    }
}

/// Writes the station of `seed` into `dir` (created if missing); returns the files and the
/// station.
pub fn write_files(dir: &Path, seed: u64) -> Result<(Vec<PathBuf>, Station), WriteError> {
    let s = Station::generate(seed);
    let lines = |v: Vec<String>| v.into_iter().map(|n| n + "\n").collect::<String>();
    let files = [
        ("plant.smv", s.plant()),
        ("station.ltl", s.properties()),
        ("station.traces", s.traces()),
        ("station.inputs", lines(s.inputs())),
        ("station.outputs", lines(s.outputs())),
    ];
    let mut out = Vec::new();
    for (name, text) in files {
        let path = dir.join(name);
        write_atomic(&path, text.as_bytes())?;
        out.push(path);
    }
    Ok((out, s))
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Every seed gives a station of the promised shape, the same one every time, and its
    /// reference controller replays its own recorded run.
    #[test]
    fn stations_have_their_shape_and_their_reference_replays_the_run() {
        for seed in 0..20 {
            let s = Station::generate(seed);
            assert!((3..=4).contains(&s.cylinders), "seed {seed}");
            assert!((2..=3).contains(&s.requests.len()), "seed {seed}");
            for strokes in &s.requests {
                assert!((2..=3).contains(&strokes.len()), "seed {seed}");
                assert!(strokes.windows(2).all(|w| w[0] != w[1]), "seed {seed}");
            }
            assert_eq!(s.traces(), Station::generate(seed).traces());
            let dir = tempfile::tempdir().unwrap();
            write_files(dir.path(), seed).unwrap();
            let set = crate::scenario::fbsat::read(
                &dir.path().join("station.traces"),
                Some(s.inputs()),
                Some(s.outputs()),
            )
            .unwrap();
            assert_eq!(set.step_count(), STEPS);
            assert!(set.check(&s.reference()).is_ok(), "seed {seed}");
        }
    }
}
