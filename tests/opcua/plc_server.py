"""A simulated PLC as an OPC UA server, for the tests of `synth record` and `synth monitor`.

The PLC replays a closed-loop run of one of the project's cases: a CSV log in the format the
tool reads (`time,scenario,in:NAME,...,out:NAME,...`), which the test writes from the case's
reference controller and plant simulation. Every input and output is a Boolean variable with
the string node id `ns=2;s=NAME` under Objects/PLC. One row is one scan: every variable's
value is read from the scan in force, replaced whole, so a Read of all of them sees one scan.

The run starts when the first client session is activated (a PLC and a monitor started
together), after holding the first row for --hold seconds; each following row lasts --scan
seconds, the last one is held until the server stops. With --break-after S, the logic breaks S
seconds after the start: from then on the first output is inverted. With --certs the only
endpoint is Basic256Sha256 (sign and encrypt), with a self-signed certificate made there.

The server listens on 127.0.0.1 only, writes "ready" on stdout once it accepts connections,
and stops by itself after --lifetime seconds (or on SIGTERM).
"""

import argparse
import asyncio
import csv
import sys
import time
from pathlib import Path

from asyncua import Server, ua
from asyncua.crypto.cert_gen import setup_self_signed_certificate
from cryptography.x509.oid import ExtendedKeyUsageOID
from asyncua.server.internal_session import InternalSession


def read_log(path):
    with open(path, newline="") as f:
        rows = list(csv.reader(f))
    header = rows[0]
    inputs = [h[3:] for h in header if h.startswith("in:")]
    outputs = [h[4:] for h in header if h.startswith("out:")]
    cols = [i for i, h in enumerate(header) if h.startswith(("in:", "out:"))]
    scans = [[row[i] in ("1", "true", "True") for i in cols] for row in rows[1:] if row]
    return inputs + outputs, len(inputs), scans


async def main():
    p = argparse.ArgumentParser()
    p.add_argument("--port", type=int, required=True)
    p.add_argument("--replay", required=True)
    p.add_argument("--scan", type=float, default=0.2)
    p.add_argument("--hold", type=float, default=1.0)
    p.add_argument("--break-after", type=float, default=None)
    p.add_argument("--lifetime", type=float, default=60.0)
    p.add_argument("--certs", help="folder for the server's key and certificate (made on first use): requires Basic256Sha256")
    args = p.parse_args()

    names, n_inputs, scans = read_log(args.replay)
    server = Server()
    await server.init()
    server.set_endpoint(f"opc.tcp://127.0.0.1:{args.port}/plc")
    server.set_server_name("fbsynth test PLC")
    await server.set_application_uri("urn:fbsynth:test-plc")
    if args.certs:
        key, cert = Path(args.certs) / "server_key.pem", Path(args.certs) / "server_cert.der"
        await setup_self_signed_certificate(
            key, cert, "urn:fbsynth:test-plc", "127.0.0.1",
            [ExtendedKeyUsageOID.SERVER_AUTH, ExtendedKeyUsageOID.CLIENT_AUTH],
            {"commonName": "fbsynth test PLC"},
        )
        await server.load_certificate(str(cert))
        await server.load_private_key(str(key))
        server.set_security_policy([ua.SecurityPolicyType.Basic256Sha256_SignAndEncrypt])
    else:
        server.set_security_policy([ua.SecurityPolicyType.NoSecurity])
    ns = await server.register_namespace("urn:fbsynth:test-plc:signals")  # index 2
    plc = await server.nodes.objects.add_object(ua.NodeId("PLC", ns), "PLC")
    # The scan in force: every variable's value is read from it, so one Read sees one scan.
    state = {"values": list(scans[0])}
    for k, name in enumerate(names):
        var = await plc.add_variable(ua.NodeId(name, ns), name, False, ua.VariantType.Boolean)
        server.iserver.aspace.set_attribute_value_callback(
            var.nodeid,
            ua.AttributeIds.Value,
            lambda _node, _attr, k=k: ua.DataValue(
                Value=
                ua.Variant(state["values"][k], ua.VariantType.Boolean)
            ),
        )

    def write(row, broken):
        values = list(row)
        if broken:
            values[n_inputs] = not values[n_inputs]
        state["values"] = values

    write(scans[0], False)
    async with server:
        print("ready", flush=True)
        deadline = time.monotonic() + args.lifetime
        while InternalSession._current_connections == 0 and time.monotonic() < deadline:
            await asyncio.sleep(0.01)
        start = time.monotonic()
        await asyncio.sleep(args.hold)
        for k, row in enumerate(scans[1:]):
            broken = args.break_after is not None and time.monotonic() - start >= args.break_after
            write(row, broken)
            next_scan = start + args.hold + (k + 1) * args.scan
            await asyncio.sleep(max(0.0, next_scan - time.monotonic()))
        while time.monotonic() < deadline:
            broken = args.break_after is not None and time.monotonic() - start >= args.break_after
            write(scans[-1], broken)
            await asyncio.sleep(args.scan)


if __name__ == "__main__":
    try:
        asyncio.run(main())
    except KeyboardInterrupt:
        sys.exit(0)
