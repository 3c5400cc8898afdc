#!/usr/bin/env python3
"""Load an XES event log with pm4py, discover a Petri net with the inductive miner, print a
summary; optionally import a PNML net and replay the log on it (token-based replay).

Usage: pm4py_check.py LOG.xes [--pnml NET.pnml] [--replay OTHER.xes]

Prints `key: value` lines (traces, events, activities, places, transitions, inductive_fitness;
with --pnml: pnml_places, pnml_transitions, pnml_labels, pnml_fitness, pnml_fitting_traces;
with --replay, the log OTHER replayed on the net discovered from LOG and on the PNML net:
replay_traces, replay_inductive_fitness, replay_inductive_fitting_traces, replay_pnml_fitness,
replay_pnml_fitting_traces) and exits 0; any error exits 1 with a message on stderr. Used by fbsynth's interoperability test with the XES that `synth events` writes.
"""
import argparse
import sys


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("log")
    parser.add_argument("--pnml")
    parser.add_argument("--replay")
    args = parser.parse_args()
    try:
        import pm4py

        log = pm4py.read_xes(args.log)
        traces = log["case:concept:name"].nunique()
        events = len(log)
        activities = log["concept:name"].nunique()
        if traces == 0 or events == 0:
            raise ValueError(f"{args.log}: no traces or no events")
        net, im, fm = pm4py.discover_petri_net_inductive(log)
        print(f"pm4py: {pm4py.__version__}")
        print(f"traces: {traces}")
        print(f"events: {events}")
        print(f"activities: {activities}")
        print(f"places: {len(net.places)}")
        print(f"transitions: {len(net.transitions)}")
        fit = pm4py.fitness_token_based_replay(log, net, im, fm)
        print(f"inductive_fitness: {fit['log_fitness']:.4f}")
        if args.pnml:
            pnet, pim, pfm = pm4py.read_pnml(args.pnml)
            print(f"pnml_places: {len(pnet.places)}")
            print(f"pnml_transitions: {len(pnet.transitions)}")
            labels = {t.label for t in pnet.transitions if t.label is not None}
            print(f"pnml_labels: {len(labels)}")
            if pfm is not None and len(pfm) > 0:
                pfit = pm4py.fitness_token_based_replay(log, pnet, pim, pfm)
                print(f"pnml_fitness: {pfit['log_fitness']:.4f}")
                fitting = round(pfit["percentage_of_fitting_traces"] * traces / 100)
                print(f"pnml_fitting_traces: {fitting}")
        if args.replay:
            other = pm4py.read_xes(args.replay)
            n = other["case:concept:name"].nunique()
            print(f"replay_traces: {n}")
            nets = [("inductive", (net, im, fm))]
            if args.pnml:
                nets.append(("pnml", (pnet, pim, pfm)))
            for key, (rn, ri, rf) in nets:
                r = pm4py.fitness_token_based_replay(other, rn, ri, rf)
                print(f"replay_{key}_fitness: {r['log_fitness']:.4f}")
                fitting = round(r["percentage_of_fitting_traces"] * n / 100)
                print(f"replay_{key}_fitting_traces: {fitting}")
    except Exception as e:  # any failure is a failed check
        print(f"pm4py_check: error: {type(e).__name__}: {e}", file=sys.stderr)
        return 1
    return 0


if __name__ == "__main__":
    sys.exit(main())
