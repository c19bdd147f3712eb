// Zero-setup install of the tvl-lsp server, as Microsoft's Python tool extensions do it: the .vsix
// carries the tvl-lsp wheel (server/tvl_lsp-*.whl); when no server is configured or on PATH, the
// extension makes a private virtual environment under its global storage, installs that wheel
// and its dependencies (from the package index pip is configured with) into it, and starts the
// server from there. The environment's folder is keyed by the extension's version and the wheel's
// hash, so an updated extension sets up (and uses) a new one; older ones are removed.
//
// Nothing here knows VS Code: extension.ts passes a progress callback and a log.
import * as cp from 'child_process';
import * as crypto from 'crypto';
import * as fs from 'fs';
import * as path from 'path';

export const MIN_PYTHON: [number, number] = [3, 10];
const READY = '.tvl-lsp-ready';
const LOCK_STALE_MS = 15 * 60 * 1000;
const PROBE =
  'import json, sys\n' +
  'ok = True\n' +
  'try:\n    import venv, ensurepip\nexcept Exception:\n    ok = False\n' +
  'print(json.dumps({"version": list(sys.version_info[:3]), "venv": ok, "executable": sys.executable}))';

export interface ServerCommand {
  command: string;
  args: string[];
  description: string;
}

export interface BootstrapOptions {
  /** the extension's own folder (context.extensionPath) */
  extensionDir: string;
  /** the extension's version (package.json) */
  extensionVersion: string;
  /** where the environments live (context.globalStorageUri.fsPath) */
  storageDir: string;
  /** Python interpreters to try, in order (settings first, then PATH names) */
  pythonCandidates: string[];
  log: (line: string) => void;
  progress: (message: string) => void;
}

export interface PythonInfo {
  python: string;
  version: number[];
}

/** The wheel shipped inside the extension, if any. */
export function bundledWheel(extensionDir: string): string | undefined {
  const dir = path.join(extensionDir, 'server');
  let names: string[];
  try {
    names = fs.readdirSync(dir);
  } catch {
    return undefined;
  }
  const wheels = names.filter((n) => /^tvl_lsp-.*\.whl$/.test(n)).sort();
  return wheels.length ? path.join(dir, wheels[wheels.length - 1]) : undefined;
}

/** The folder name of the environment for this extension version and wheel. */
export function environmentKey(extensionVersion: string, wheel: string): string {
  const hash = crypto.createHash('sha256').update(fs.readFileSync(wheel) as unknown as crypto.BinaryLike).digest('hex').slice(0, 12);
  return `${extensionVersion.replace(/[^A-Za-z0-9.+-]/g, '_')}-${hash}`;
}

export function venvPython(venv: string): string {
  return process.platform === 'win32' ? path.join(venv, 'Scripts', 'python.exe') : path.join(venv, 'bin', 'python');
}

function serverIn(venv: string): ServerCommand {
  const python = venvPython(venv);
  return { command: python, args: ['-m', 'tvl_lsp'], description: `${python} -m tvl_lsp (set up by the extension)` };
}

/** The first candidate that is Python >= 3.10 able to create virtual environments, or why none is. */
export function findPython(candidates: string[]): PythonInfo | string {
  const tried: string[] = [];
  const seen = new Set<string>();
  for (const cand of candidates) {
    if (!cand || seen.has(cand)) {
      continue;
    }
    seen.add(cand);
    const r = cp.spawnSync(cand, ['-c', PROBE], { encoding: 'utf8', timeout: 20000 });
    if (r.error || r.status !== 0) {
      if (r.error && (r.error as NodeJS.ErrnoException).code !== 'ENOENT') {
        tried.push(`${cand}: cannot be run (${r.error.message})`);
      } else if (!r.error) {
        tried.push(`${cand}: exits with status ${r.status}`);
      }
      continue;
    }
    let info: { version: number[]; venv: boolean; executable: string };
    try {
      info = JSON.parse(r.stdout.trim().split('\n').pop() ?? '');
    } catch {
      tried.push(`${cand}: not a Python interpreter`);
      continue;
    }
    const v = info.version.join('.');
    if (info.version[0] < MIN_PYTHON[0] || (info.version[0] === MIN_PYTHON[0] && info.version[1] < MIN_PYTHON[1])) {
      tried.push(`${cand} is Python ${v}`);
      continue;
    }
    if (!info.venv) {
      tried.push(`${cand} (Python ${v}) cannot create virtual environments (on Debian and Ubuntu: apt install python3-venv)`);
      continue;
    }
    return { python: cand, version: info.version };
  }
  const want = `${MIN_PYTHON[0]}.${MIN_PYTHON[1]}`;
  return (
    `The TVL extension needs Python ${want} or newer to set up its language server, and found none` +
    (tried.length ? ` (${tried.join('; ')})` : ' on PATH') +
    `. Install Python ${want}+ and reload the window, or set "tvl-lsp.server.setupPython" to such an interpreter` +
    ` (or install tvl-lsp yourself and set "tvl-lsp.server.path").`
  );
}

function run(cmd: string, args: string[], log: (l: string) => void): Promise<{ code: number | null; tail: string }> {
  return new Promise((resolve) => {
    log(`$ ${cmd} ${args.join(' ')}`);
    let tail = '';
    const p = cp.spawn(cmd, args, { env: { ...process.env, PIP_DISABLE_PIP_VERSION_CHECK: '1', PIP_NO_INPUT: '1' } });
    const onData = (b: Buffer) => {
      const s = b.toString();
      tail = (tail + s).slice(-4000);
      for (const line of s.split(/\r?\n/)) {
        if (line.trim()) {
          log(line);
        }
      }
    };
    p.stdout.on('data', onData);
    p.stderr.on('data', onData);
    p.on('error', (e) => resolve({ code: -1, tail: tail + String(e) }));
    p.on('close', (code) => resolve({ code, tail }));
  });
}

function sleep(ms: number): Promise<void> {
  return new Promise((r) => setTimeout(r, ms));
}

/** The server already set up for this version, if any (no work, no messages). */
export function readyServer(opts: Pick<BootstrapOptions, 'extensionDir' | 'extensionVersion' | 'storageDir'>): ServerCommand | undefined {
  const wheel = bundledWheel(opts.extensionDir);
  if (!wheel) {
    return undefined;
  }
  const venv = path.join(opts.storageDir, 'server', environmentKey(opts.extensionVersion, wheel));
  return fs.existsSync(path.join(venv, READY)) && fs.existsSync(venvPython(venv)) ? serverIn(venv) : undefined;
}

/**
 * The server in the extension's private environment, set up first if needed. Returns the
 * command, or a message for the user saying what went wrong and what to do.
 */
export async function ensureServer(opts: BootstrapOptions): Promise<ServerCommand | string> {
  const wheel = bundledWheel(opts.extensionDir);
  if (!wheel) {
    return 'This build of the TVL extension carries no tvl-lsp wheel to set up.';
  }
  const root = path.join(opts.storageDir, 'server');
  const key = environmentKey(opts.extensionVersion, wheel);
  const venv = path.join(root, key);
  const ready = path.join(venv, READY);
  const lock = venv + '.lock';
  fs.mkdirSync(root, { recursive: true });

  // one window sets up; the others wait for it
  for (;;) {
    if (fs.existsSync(ready) && fs.existsSync(venvPython(venv))) {
      return serverIn(venv);
    }
    try {
      fs.mkdirSync(lock);
      break;
    } catch {
      let age = 0;
      try {
        age = Date.now() - fs.statSync(lock).mtimeMs;
      } catch {
        continue;
      }
      if (age > LOCK_STALE_MS) {
        fs.rmSync(lock, { recursive: true, force: true });
        continue;
      }
      opts.progress('waiting for another window that is setting up the server');
      await sleep(1000);
    }
  }
  try {
    opts.progress('looking for Python ≥ 3.10');
    const py = findPython(opts.pythonCandidates);
    if (typeof py === 'string') {
      return py;
    }
    opts.log(`Setting up tvl-lsp from ${path.basename(wheel)} in ${venv} with ${py.python} (Python ${py.version.join('.')})`);
    fs.rmSync(venv, { recursive: true, force: true });
    opts.progress(`creating a virtual environment (Python ${py.version.join('.')})`);
    let r = await run(py.python, ['-m', 'venv', venv], opts.log);
    if (r.code !== 0) {
      return `The TVL extension could not create a virtual environment with ${py.python}: ${lastLine(r.tail)}. See the output for details.`;
    }
    opts.progress('installing tvl-lsp and its dependencies (pip)');
    r = await run(venvPython(venv), ['-m', 'pip', 'install', '--no-input', '--disable-pip-version-check', wheel], opts.log);
    if (r.code !== 0) {
      return (
        `The TVL extension could not install its language server with pip: ${lastLine(r.tail)}. ` +
        'pip needs to reach the package index (PyPI) once for the server\'s dependencies; see the output for details, then run "TVL: Restart the language server".'
      );
    }
    opts.progress('checking the installed server');
    r = await run(venvPython(venv), ['-m', 'tvl_lsp', '--version'], opts.log);
    if (r.code !== 0) {
      return `The language server installed by the TVL extension does not start: ${lastLine(r.tail)}. See the output for details.`;
    }
    fs.writeFileSync(ready, JSON.stringify({ wheel: path.basename(wheel), python: py.python, version: py.version, at: new Date().toISOString() }) + '\n');
    // environments of other extension versions are no longer used
    for (const name of fs.readdirSync(root)) {
      if (name !== key && name !== path.basename(lock) && !name.endsWith('.lock')) {
        fs.rmSync(path.join(root, name), { recursive: true, force: true });
      }
    }
    opts.log(`tvl-lsp is set up in ${venv}`);
    return serverIn(venv);
  } finally {
    fs.rmSync(lock, { recursive: true, force: true });
  }
}

function lastLine(text: string): string {
  const lines = text.split(/\r?\n/).map((l) => l.trim()).filter((l) => l);
  const err = lines.filter((l) => /error/i.test(l)).pop();
  return (err ?? lines.pop() ?? 'no output').slice(0, 300);
}
