"""The workspace-scale LSP scenario (`bench.py linked`): a densely linked workspace with every
file open, declaration edits, idle requests and memory, run on gudsl and on the Langium anchor
alternately with one stdlib-only client (a reader thread timestamps each message as it arrives).
See bench.py's docstring for the command line."""

import argparse
import json
import os
import re
import statistics
import subprocess
import threading
import time
from pathlib import Path


class Client:
    """JSON-RPC over a server's stdio; every incoming message is timestamped when read."""

    def __init__(self, cmd, cwd):
        self.t_launch = time.perf_counter()
        self.proc = subprocess.Popen(cmd, cwd=cwd, stdin=subprocess.PIPE, stdout=subprocess.PIPE,
                                     stderr=open(os.environ.get("LSP_STDERR", os.devnull), "ab"))
        self.next_id = 1
        self.cv = threading.Condition()
        self.responses = {}
        self.diags = []  # (time, uri, version, diagnostics)
        self.write_lock = threading.Lock()
        threading.Thread(target=self._read, daemon=True).start()

    def _send(self, message):
        body = json.dumps(message).encode()
        with self.write_lock:
            self.proc.stdin.write(b"Content-Length: %d\r\n\r\n" % len(body) + body)
            self.proc.stdin.flush()

    def _read(self):
        out = self.proc.stdout
        while True:
            length = None
            while True:
                line = out.readline()
                if not line:
                    with self.cv:
                        self.cv.notify_all()
                    return
                line = line.strip()
                if not line:
                    break
                if line.lower().startswith(b"content-length:"):
                    length = int(line.split(b":")[1])
            message = json.loads(out.read(length))
            now = time.perf_counter()
            if "id" in message and "method" in message:  # the server's own request
                self._send({"jsonrpc": "2.0", "id": message["id"], "result": None})
                continue
            with self.cv:
                if "id" in message:
                    self.responses[message["id"]] = (now, message)
                elif message.get("method") == "textDocument/publishDiagnostics":
                    p = message["params"]
                    self.diags.append((now, p["uri"], p.get("version"), p["diagnostics"]))
                self.cv.notify_all()

    def notify(self, method, params):
        self._send({"jsonrpc": "2.0", "method": method, "params": params})

    def request(self, method, params, timeout=120):
        """(seconds until the answer, result)."""
        rid = self.next_id
        self.next_id += 1
        t0 = time.perf_counter()
        self._send({"jsonrpc": "2.0", "id": rid, "method": method, "params": params})
        with self.cv:
            if not self.cv.wait_for(lambda: rid in self.responses or self.proc.poll() is not None, timeout):
                raise SystemExit(f"{method}: no answer in {timeout} s")
            if rid not in self.responses:
                raise SystemExit(f"{method}: the server exited ({self.proc.poll()})")
            t, message = self.responses.pop(rid)
        if "error" in message:
            raise SystemExit(f"{method}: {message['error']}")
        return t - t0, message.get("result")

    def wait_diagnostics(self, uri, since, pred, timeout=60):
        """The first publish for `uri` at index >= since that satisfies pred, or None."""
        deadline = time.perf_counter() + timeout
        with self.cv:
            while True:
                for entry in self.diags[since:]:
                    if entry[1] == uri and pred(entry):
                        return entry
                left = deadline - time.perf_counter()
                if left <= 0 or self.proc.poll() is not None:
                    return None
                self.cv.wait(left)

    def wait_quiet(self, quiet=2.0, timeout=300):
        """Until no diagnostics arrived for `quiet` seconds."""
        end = time.perf_counter() + timeout
        while time.perf_counter() < end:
            n = len(self.diags)
            time.sleep(quiet)
            if len(self.diags) == n:
                return

    def rss_mib(self):
        for line in Path(f"/proc/{self.proc.pid}/status").read_text().splitlines():
            if line.startswith("VmRSS:"):
                return int(line.split()[1]) / 1024
        return float("nan")

    def shutdown(self):
        try:
            self.request("shutdown", None, timeout=10)
            self.notify("exit", None)
            self.proc.wait(timeout=10)
        except (SystemExit, subprocess.TimeoutExpired, BrokenPipeError):
            self.proc.kill()


def percentiles(xs):
    xs = sorted(xs)
    q = lambda p: xs[min(len(xs) - 1, int(round(p * (len(xs) - 1))))]
    return {"n": len(xs), "p50_ms": round(q(0.5) * 1e3, 2), "p95_ms": round(q(0.95) * 1e3, 2),
            "max_ms": round(xs[-1] * 1e3, 2)}


def position(text, pattern, group_offset=None):
    """(line, character) of the first match of pattern's group 1: its end, or its start plus
    group_offset."""
    for ln, line in enumerate(text.split("\n")):
        m = re.search(pattern, line)
        if m:
            return ln, (m.end(1) if group_offset is None else m.start(1) + group_offset)
    raise ValueError(pattern)


def offset(text, ln, ch):
    return sum(len(l) + 1 for l in text.split("\n")[:ln]) + ch


def cpu_sample(server_pid):
    """(time, busy jiffies of the machine, jiffies of the server and this client)."""
    with open("/proc/stat") as f:
        v = [int(x) for x in f.readline().split()[1:]]
    mine = 0
    for pid in (server_pid, os.getpid()):
        with open(f"/proc/{pid}/stat") as f:
            fields = f.read().rsplit(")", 1)[1].split()
        mine += int(fields[11]) + int(fields[12])
    return time.perf_counter(), sum(v) - v[3] - v[4], mine


def other_load(a, b):
    """Cores used by other processes than the server and the client between two samples."""
    hz = os.sysconf("SC_CLK_TCK")
    return round(max(0, (b[1] - a[1]) - (b[2] - a[2])) / hz / (b[0] - a[0]), 2)


class Language:
    """What differs between the two servers: file names, the written forms the keystrokes edit
    and the requests point at, and how an unresolved name reads in a diagnostic."""

    def __init__(self, kind):
        self.kind = kind
        if kind == "gudsl":
            self.suffix, self.language_id = ".gudsl", "gudsl"
            self.class_re = r"public class (E1_{k})\b"
            self.field_type_re = r"public (String) name;"
            self.completion_re, self.hover_re = r"items : (E)\d", r"public M\d+\.(E)\d"
            self.references_re = r"public class (E1_5)\b"
        else:
            self.suffix, self.language_id = ".dmodel", "langium"
            self.class_re = r"entity (E1_{k})\b"
            self.field_type_re = r"name: (String)\b"
            self.completion_re, self.hover_re = r"many items: (E)\d", r"owner: m\d+\.(E)\d"
            self.references_re = r"entity (E1_5)\b"

    def unresolved(self, diagnostics):
        """The names the diagnostics say are unresolved (one per diagnostic), or None if a
        diagnostic is about something else."""
        names = []
        for d in diagnostics:
            m = re.search(r"named '([^']+)'", d["message"]) if self.kind == "langium" else \
                re.search(r"`([A-Za-z_][A-Za-z0-9_.]*)`", d["message"])
            if not m:
                return None
            names.append(m.group(1))
        return names


def run_once(kind, cmd, workspace, edited="f001"):
    lang = Language(kind)
    files = sorted(p for p in Path(workspace).iterdir() if p.suffix == lang.suffix)
    texts = {p: p.read_text() for p in files}
    result = {"server": kind, "files": len(files), "lines": sum(t.count("\n") for t in texts.values())}
    client = Client(cmd, cwd=str(workspace))
    load = [cpu_sample(client.proc.pid)]
    root = Path(workspace).resolve().as_uri()
    client.request("initialize", {
        "processId": os.getpid(), "rootUri": root, "workspaceFolders": [{"uri": root, "name": "ws"}],
        "capabilities": {"textDocument": {"publishDiagnostics": {"versionSupport": True},
                                          "hover": {"contentFormat": ["markdown", "plaintext"]}},
                         "workspace": {"workspaceFolders": True, "configuration": True}}})
    client.notify("initialized", {})
    for p in files:
        client.notify("textDocument/didOpen", {"textDocument": {
            "uri": p.resolve().as_uri(), "languageId": lang.language_id, "version": 1, "text": texts[p]}})
    last_first_publish = 0.0
    for p in files:
        entry = client.wait_diagnostics(p.resolve().as_uri(), 0, lambda e: True, timeout=300)
        if entry is None:
            raise SystemExit(f"{kind}: no diagnostics for {p.name}")
        last_first_publish = max(last_first_publish, entry[0])
    result["cold_start_ms"] = round((last_first_publish - client.t_launch) * 1e3, 1)
    client.wait_quiet()
    last = {}
    for entry in client.diags:
        last[entry[1]] = entry[3]
    result["initial_diagnostics"] = sum(len(d) for d in last.values())
    result["rss_after_load_mib"] = round(client.rss_mib(), 1)

    load.append(cpu_sample(client.proc.pid))
    target = next(p for p in files if p.stem == edited)
    uri, text = target.resolve().as_uri(), texts[target]
    version, latencies, wrong_versions = 1, [], 0
    for block in range(50):
        k = 1 + block % 19
        class_at = position(text, lang.class_re.format(k=k))
        lines = text.split("\n")
        type_at = position("\n".join(lines[class_at[0]:]), lang.field_type_re)
        type_at = (type_at[0] + class_at[0], type_at[1])
        steps = [(type_at, "X", {"StringX"}), (class_at, "Z", {"StringX", f"E1_{k}"}),
                 (type_at, "", {f"E1_{k}"}), (class_at, "", set())]
        for (ln, ch), inserted, expected in steps:
            if inserted:
                change = {"range": {"start": {"line": ln, "character": ch}, "end": {"line": ln, "character": ch}},
                          "text": inserted}
                o = offset(text, ln, ch)
                text = text[:o] + inserted + text[o:]
            else:
                change = {"range": {"start": {"line": ln, "character": ch}, "end": {"line": ln, "character": ch + 1}},
                          "text": ""}
                o = offset(text, ln, ch)
                text = text[:o] + text[o + 1:]
            version += 1

            def matches(entry, expected=expected):
                names = lang.unresolved(entry[3])
                return names is not None and len(names) == len(expected) and set(names) == expected

            since = len(client.diags)
            sent = time.perf_counter()
            client.notify("textDocument/didChange", {"textDocument": {"uri": uri, "version": version},
                                                     "contentChanges": [change]})
            entry = client.wait_diagnostics(uri, since, matches)
            if entry is None:
                seen = [e[3] for e in client.diags[since:] if e[1] == uri][-1:]
                raise SystemExit(f"{kind}: keystroke {version}: expected {expected}, last published {seen}")
            if kind == "gudsl" and entry[2] != version:
                wrong_versions += 1
            latencies.append(entry[0] - sent)
            time.sleep(max(0.0, 0.1 - (time.perf_counter() - sent)))
    assert text == texts[target], "the client's text drifted"
    result["keystroke_to_diagnostics"] = percentiles(latencies)
    result["keystroke_by_step_ms"] = {name: percentiles(latencies[i::4]) for i, name in
                                      enumerate(["type made unknown", "class renamed", "type restored", "class restored"])}
    if kind == "gudsl":
        result["matching_publish_with_another_version"] = wrong_versions
    load.append(cpu_sample(client.proc.pid))
    client.wait_quiet()
    result["rss_after_typing_mib"] = round(client.rss_mib(), 1)

    requests = [
        ("completion", "textDocument/completion", position(text, lang.completion_re, 1)),
        ("hover", "textDocument/hover", position(text, lang.hover_re, 1)),
        ("definition", "textDocument/definition", position(text, lang.hover_re, 1)),
        ("references", "textDocument/references", position(text, lang.references_re, 1)),
    ]
    for name, method, (ln, ch) in requests:
        params = {"textDocument": {"uri": uri}, "position": {"line": ln, "character": ch}}
        if name == "references":
            params["context"] = {"includeDeclaration": True}
        times = []
        for _ in range(100):
            seconds, answer = client.request(method, params)
            times.append(seconds)
        size = len(answer) if isinstance(answer, list) else \
            len(answer.get("items", [])) if isinstance(answer, dict) and "items" in answer else int(answer is not None)
        result[name] = dict(percentiles(times), answer_size=size)
    result["rss_after_requests_mib"] = round(client.rss_mib(), 1)
    load.append(cpu_sample(client.proc.pid))
    result["other_processes_cores"] = {phase: other_load(load[i], load[i + 1])
                                       for i, phase in enumerate(["load", "typing", "requests"])}
    client.shutdown()
    return result


ROWS = [
    ("keystroke -> diagnostics p50 / p95 ms", lambda r: (r["keystroke_to_diagnostics"]["p50_ms"], r["keystroke_to_diagnostics"]["p95_ms"])),
    ("completion p50 / p95 ms", lambda r: (r["completion"]["p50_ms"], r["completion"]["p95_ms"])),
    ("hover p50 / p95 ms", lambda r: (r["hover"]["p50_ms"], r["hover"]["p95_ms"])),
    ("definition p50 / p95 ms", lambda r: (r["definition"]["p50_ms"], r["definition"]["p95_ms"])),
    ("references p50 / p95 ms", lambda r: (r["references"]["p50_ms"], r["references"]["p95_ms"])),
    ("cold start (launch -> all diagnostics) ms", lambda r: (r["cold_start_ms"],)),
    ("RSS after load -> after typing MiB", lambda r: (r["rss_after_load_mib"], r["rss_after_typing_mib"])),
    ("other processes while typing, cores", lambda r: (r["other_processes_cores"]["typing"],)),
]


def summary(runs):
    """Per server and row, the median over runs of each figure."""
    out = {}
    for server in sorted({r["server"] for r in runs}):
        mine = [r for r in runs if r["server"] == server]
        out[server] = {}
        for label, get in ROWS:
            values = [get(r) for r in mine]
            out[server][label] = tuple(round(statistics.median(v[i] for v in values), 1)
                                       for i in range(len(values[0])))
    return out


def main(argv):
    parser = argparse.ArgumentParser(prog="bench.py linked")
    parser.add_argument("--gudsl", required=True, help="the gudsl binary")
    parser.add_argument("--workspace", required=True, help="a linked workspace (synth --linked)")
    parser.add_argument("--langium", help="the anchor's server command, e.g. 'node …/main.js --stdio'")
    parser.add_argument("--langium-workspace", help="the anchor's dmodel workspace")
    parser.add_argument("--runs", type=int, default=3)
    parser.add_argument("--out", help="write every run's figures to this JSON file")
    args = parser.parse_args(argv)
    servers = [("gudsl", [str(Path(args.gudsl).resolve()), "lsp"], args.workspace)]
    if args.langium:
        servers.append(("langium", args.langium.split(), args.langium_workspace))
    runs = []
    for n in range(args.runs):
        for kind, cmd, workspace in servers:
            result = run_once(kind, cmd, workspace)
            result["run"] = n + 1
            runs.append(result)
            print(json.dumps(result), flush=True)
    if args.out:
        Path(args.out).write_text(json.dumps(runs, indent=1))
    table = summary(runs)
    names = list(table)
    print(f"\n| median of {args.runs} runs | " + " | ".join(
        f"{n} ({next(r['files'] for r in runs if r['server'] == n)} files)" for n in names) + " |")
    print("|---|" + "---|" * len(names))
    for label, _ in ROWS:
        print(f"| {label} | " + " | ".join(" / ".join(f"{v:g}" for v in table[n][label]) for n in names) + " |")
