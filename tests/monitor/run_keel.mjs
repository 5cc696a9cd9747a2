// Test support: `keel run PROFILE --monitor 127.0.0.1:0 ...` (or another server printing the same
// line) started for a test, its monitor's address read from the line it prints, and the npm peers (Foxglove's client, ws) resolved from
// tests/peers, where scripts/peers.sh installs them.
import { spawn } from "node:child_process";
import { createRequire } from "node:module";
import path from "node:path";
import { fileURLToPath } from "node:url";

export const repo = path.resolve(path.dirname(fileURLToPath(import.meta.url)), "../..");
export const peers = createRequire(path.join(repo, "tests/peers/package.json"));

/** The keel command under test: $KEEL_CLI (CTest gives it), else the default build's. */
export const keelCli = process.env.KEEL_CLI || path.join(repo, "build/bin/keel");
/** keel's test components (tests/integration/components): $KEEL_TEST_COMPONENTS, else the default build's. */
export const testComponents = process.env.KEEL_TEST_COMPONENTS || path.join(repo, "build/tests/components");

/**
 * Starts `cmd args` (keel run --monitor, or the page test's mock server) and resolves once it
 * printed its monitor line: { url, token, port, host, child, output() }.
 */
export function serve(cmd, args, { timeoutMs = 20000, env = {} } = {}) {
  const child = spawn(cmd, args, { cwd: repo, env: { ...process.env, ...env }, stdio: ["ignore", "pipe", "pipe"] });
  let out = "";
  let err = "";
  child.stderr.on("data", (d) => (err += d));
  return new Promise((resolve, reject) => {
    const timer = setTimeout(() => reject(new Error(`${cmd} printed no monitor line:\n${out}\n${err}`)), timeoutMs);
    const early = (code, signal) => {
      clearTimeout(timer);
      reject(new Error(`${cmd} exited (${code ?? signal}) before serving:\n${out}\n${err}`));
    };
    child.once("exit", early);
    let served = false;
    child.stdout.on("data", (d) => {
      out += d;
      if (served) return;
      const m = out.match(/^monitor: (http:\/\/([^/]+)\/\?token=([0-9a-f]+))$/m);
      if (!m) return;
      served = true;
      clearTimeout(timer);
      child.off("exit", early);
      resolve({
        url: m[1],
        host: m[2],
        port: Number(m[2].split(":").pop()),
        token: m[3],
        child,
        output: () => out + err,
      });
    });
  });
}

/** keel run with `args` and --monitor on a free port, as serve() starts it. */
export function startKeel(args, options = {}) {
  return serve(keelCli, ["run", ...args, "--monitor", "127.0.0.1:0"], options);
}

/** Stops what serve() started (SIGINT: a clean stop; SIGKILL after 5 s) and resolves with its exit code. */
export function stopKeel(run) {
  return new Promise((resolve) => {
    if (run.child.exitCode !== null) return resolve(run.child.exitCode);
    const kill = setTimeout(() => run.child.kill("SIGKILL"), 5000);
    run.child.once("exit", (code, signal) => {
      clearTimeout(kill);
      resolve(code ?? 128);
    });
    run.child.kill("SIGINT");
  });
}

/** Resolves with the first value `probe` returns that is not undefined, polling every 10 ms. */
export async function until(probe, what, timeoutMs = 10000) {
  const end = Date.now() + timeoutMs;
  for (;;) {
    const v = probe();
    if (v !== undefined) return v;
    if (Date.now() > end) throw new Error(`timed out waiting for ${what}`);
    await new Promise((r) => setTimeout(r, 10));
  }
}
