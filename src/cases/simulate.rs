//! The closed loop every case runs: a reference controller scanned against a plant simulation.
//!
//! In: an [`Ecc`], a [`Simulated`] plant and a driver that acts on the plant between scans.
//! Out: the scans ([`Scanned`]) and the plant at the end.

use crate::ecc::{Ecc, Fired, Run};

/// A plant simulation, scanned like a PLC in closed loop with a controller.
pub trait Simulated: Clone {
    /// The sensor values the controller reads at the start of a scan.
    fn read(&self) -> Vec<bool>;
    /// Moves the plant through one scan under the controller's commands `z`.
    fn scan(&mut self, z: &[bool]);
}

/// One scan of a closed-loop run.
#[derive(Debug, Clone, PartialEq)]
pub struct Scanned<P> {
    /// The plant as the controller saw it (before it moved for this scan).
    pub plant: P,
    /// Sensor values read.
    pub inputs: Vec<bool>,
    /// The transition that fired, if any.
    pub fired: Option<Fired>,
    /// Commands after the scan (unchanged when nothing fired).
    pub outputs: Vec<bool>,
}

/// What the driver of a run decides before a scan.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Drive {
    /// Run the next scan.
    Scan,
    /// End the run here.
    Stop,
}

/// The one simulate loop of every case: `ecc` against `plant`, scan by scan. Before scan `k`
/// `drive(k, plant, scans so far)` may act on the plant (pieces arriving, buttons pressed)
/// or stop the run; it is called once more with `k == max_scans` (to see the last scan's
/// effect), after which the run ends in any case. Returns the scans and the plant at the end.
pub fn closed_loop<P: Simulated>(
    ecc: &Ecc,
    mut plant: P,
    max_scans: usize,
    mut drive: impl FnMut(usize, &mut P, &[Scanned<P>]) -> Drive,
) -> (Vec<Scanned<P>>, P) {
    let mut run = Run::new(ecc);
    let mut scans = Vec::new();
    for k in 0..=max_scans {
        if drive(k, &mut plant, &scans) == Drive::Stop || k == max_scans {
            break;
        }
        let inputs = plant.read();
        let seen = plant.clone();
        let fired = run.step(&inputs);
        plant.scan(&run.outputs);
        scans.push(Scanned {
            plant: seen,
            inputs,
            fired,
            outputs: run.outputs.clone(),
        });
    }
    (scans, plant)
}
