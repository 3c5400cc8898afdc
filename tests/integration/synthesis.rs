//! Synthesis from the runs of random machines: the result replays every run and is no larger
//! than the machine that produced them.

use crate::common::{random_ecc, record};
use fbsynth::sat::{synthesize, Options};
use fbsynth::scenario::tree::ScenarioTree;
use proptest::prelude::*;

proptest! {
    #![proptest_config(ProptestConfig { cases: 48, ..ProptestConfig::default() })]

    #[test]
    fn synthesized_machine_replays_runs_and_is_no_larger(
        seed in any::<u64>(),
        c in 1usize..=4,
        inputs in 1usize..=3,
        outputs in 1usize..=3,
        runs in 1usize..=4,
        len in 1usize..=12,
    ) {
        let gen = random_ecc(seed, c, inputs, outputs);
        let set = record(&gen, seed, runs, len);
        let tree = ScenarioTree::build(&set).expect("runs of one machine never contradict");
        let r = synthesize(&set, &tree, &Options::default(), &mut |_| {}).expect("a machine exists");
        prop_assert!(set.check(&r.ecc).is_ok());
        prop_assert!(r.size.c <= c, "synthesized {} states from a {}-state machine", r.size.c, c);
    }
}
