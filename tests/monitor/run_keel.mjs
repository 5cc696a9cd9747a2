// Test support: `keel run PROFILE --monitor 127.0.0.1:0 ...` started for a test, its monitor's
// address read from the line it prints, and the npm peers (Foxglove's client, ws) resolved from
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
 * Starts keel run with `args` and --monitor on a free port. Resolves once it printed its
 * monitor line: { url, token, port, host, child, output() }.
 */
export function startKeel(args, { timeoutMs = 20000, env = {} } = {}) {
  const child = spawn(keelCli, ["run", ...args, "--monitor", "127.0.0.1:0"], {
    cwd: repo,
    env: { ...process.env, ...env },
    stdio: ["ignore", "pipe", "pipe"],
  });
  let out = "";
  let err = "";
  child.stderr.on("data", (d) => (err += d));
  return new Promise((resolve, reject) => {
    const timer = setTimeout(() => reject(new Error(`keel run printed no monitor line:\n${out}\n${err}`)), timeoutMs);
    child.on("exit", (code) => reject(new Error(`keel run exited (${code}) before serving:\n${out}\n${err}`)));
    let served = false;
    child.stdout.on("data", (d) => {
      out += d;
      if (served) return;
      const m = out.match(/^monitor: (http:\/\/([^/]+)\/\?token=([0-9a-f]+))$/m);
      if (!m) return;
      served = true;
      clearTimeout(timer);
      child.removeAllListeners("exit");
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

/** Stops a keel run started above (SIGINT: a clean stop) and resolves with its exit code. */
export function stopKeel(run) {
  return new Promise((resolve) => {
    if (run.child.exitCode !== null) return resolve(run.child.exitCode);
    run.child.on("exit", (code) => resolve(code));
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
