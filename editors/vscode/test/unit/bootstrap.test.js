// The zero-setup install (src/bootstrap.ts): finding Python >= 3.10, the environment's key, and a
// whole set-up with a real Python and a tiny stand-in wheel (no network: the wheel has no
// dependencies). Runs the bundled client: npm run test:unit
'use strict';
const test = require('node:test');
const assert = require('node:assert');
const cp = require('child_process');
const fs = require('fs');
const os = require('os');
const path = require('path');
const { loadExtension } = require('./mock-vscode');

const bundle = path.resolve(__dirname, '..', '..', 'out', 'extension.js');
const { ext } = loadExtension(bundle, {});
const tmp = (p) => fs.mkdtempSync(path.join(os.tmpdir(), p));

/** A script that answers the interpreter probe like a Python of this version would. */
function fakePython(dir, name, version, venv) {
  const exe = path.join(dir, name);
  const info = JSON.stringify({ version, venv, executable: exe });
  fs.writeFileSync(exe, `#!/bin/sh\necho '${info}'\n`, { mode: 0o755 });
  return exe;
}

function realPython() {
  for (const p of [process.env.TVL_TEST_BARE_PYTHON, '/usr/bin/python3', 'python3']) {
    if (!p) continue;
    const r = cp.spawnSync(p, ['-c', 'import sys, venv, ensurepip; assert sys.version_info >= (3, 10)'], { encoding: 'utf8' });
    if (r.status === 0) return p;
  }
  return undefined;
}

/** A wheel of a stand-in `tvl_lsp` package whose `python -m tvl_lsp --version` prints `version`. */
function standInWheel(python, dir, version) {
  const script = `
import sys, zipfile
ver = sys.argv[2]
name = f"tvl_lsp-{ver}.dist-info"
files = {
    "tvl_lsp/__init__.py": "",
    "tvl_lsp/__main__.py": f"print('tvl-lsp {ver} (stand-in)')\\n",
    f"{name}/METADATA": f"Metadata-Version: 2.1\\nName: tvl-lsp\\nVersion: {ver}\\n",
    f"{name}/WHEEL": "Wheel-Version: 1.0\\nGenerator: test\\nRoot-Is-Purelib: true\\nTag: py3-none-any\\n",
}
files[f"{name}/RECORD"] = "".join(f"{k},,\\n" for k in files) + f"{name}/RECORD,,\\n"
with zipfile.ZipFile(sys.argv[1], "w") as z:
    for k, v in files.items():
        z.writestr(k, v)
`;
  fs.mkdirSync(dir, { recursive: true });
  const whl = path.join(dir, `tvl_lsp-${version}-py3-none-any.whl`);
  const r = cp.spawnSync(python, ['-c', script, whl, version], { encoding: 'utf8' });
  assert.strictEqual(r.status, 0, r.stderr);
  return whl;
}

test('no Python >= 3.10: the message names what was found and what to do', () => {
  const dir = tmp('py-');
  const old = fakePython(dir, 'python3.8', [3, 8, 10], true);
  const novenv = fakePython(dir, 'python3.11', [3, 11, 2], false);
  const msg = ext.findPython([old, novenv, path.join(dir, 'absent')]);
  assert.strictEqual(typeof msg, 'string');
  assert.match(msg, /needs Python 3\.10 or newer/);
  assert.match(msg, /python3\.8 is Python 3\.8\.10/);
  assert.match(msg, /python3\.11 \(Python 3\.11\.2\) cannot create virtual environments.*python3-venv/);
  assert.match(msg, /tvl-lsp\.server\.setupPython/);
});

test('the first suitable Python is chosen', () => {
  const dir = tmp('py-');
  const old = fakePython(dir, 'python3.9', [3, 9, 0], true);
  const good = fakePython(dir, 'python3.12', [3, 12, 1], true);
  assert.deepStrictEqual(ext.findPython([old, good]), { python: good, version: [3, 12, 1] });
});

test('the environment key follows the extension version and the wheel', () => {
  const dir = tmp('whl-');
  const a = path.join(dir, 'a.whl');
  const b = path.join(dir, 'b.whl');
  fs.writeFileSync(a, 'one');
  fs.writeFileSync(b, 'two');
  assert.match(ext.environmentKey('0.1.0', a), /^0\.1\.0-[0-9a-f]{12}$/);
  assert.notStrictEqual(ext.environmentKey('0.1.0', a), ext.environmentKey('0.1.0', b));
  assert.notStrictEqual(ext.environmentKey('0.1.0', a), ext.environmentKey('0.2.0', a));
});

test('no suitable Python: ensureServer says so and leaves nothing behind', async () => {
  const extDir = tmp('ext-');
  fs.mkdirSync(path.join(extDir, 'server'));
  fs.writeFileSync(path.join(extDir, 'server', 'tvl_lsp-0.1.0-py3-none-any.whl'), 'x');
  const storage = tmp('storage-');
  const msg = await ext.ensureServer({
    extensionDir: extDir, extensionVersion: '0.1.0', storageDir: storage,
    pythonCandidates: [fakePython(tmp('py-'), 'python3', [3, 9, 7], true)],
    log: () => {}, progress: () => {},
  });
  assert.match(msg, /needs Python 3\.10 or newer.*3\.9\.7/);
  assert.deepStrictEqual(fs.readdirSync(path.join(storage, 'server')), []);
});

test('set-up: a venv from the bundled wheel, reused next time, replaced when the extension is updated', async (t) => {
  const python = realPython();
  if (!python) {
    t.skip('no Python >= 3.10 with venv on this machine');
    return;
  }
  const storage = tmp('storage-');
  const v1 = tmp('ext-1-');
  standInWheel(python, path.join(v1, 'server'), '0.1.0');
  const progress = [];
  const opts = { extensionDir: v1, extensionVersion: '0.1.0', storageDir: storage, pythonCandidates: [python],
    log: () => {}, progress: (m) => progress.push(m) };
  assert.strictEqual(ext.readyServer(opts), undefined);
  const how = await ext.ensureServer(opts);
  assert.strictEqual(typeof how, 'object', String(how));
  assert.deepStrictEqual(how.args, ['-m', 'tvl_lsp']);
  assert.ok(how.command.startsWith(path.join(storage, 'server', '0.1.0-')), how.command);
  const out = cp.spawnSync(how.command, [...how.args, '--version'], { encoding: 'utf8' });
  assert.match(out.stdout, /tvl-lsp 0\.1\.0 \(stand-in\)/);
  assert.ok(progress.some((m) => /installing tvl-lsp/.test(m)), progress.join(' | '));
  // the next activation finds it without any work
  assert.deepStrictEqual(ext.readyServer(opts), how);
  // an updated extension (another version, another wheel) gets its own environment; the old one goes
  const v2 = tmp('ext-2-');
  standInWheel(python, path.join(v2, 'server'), '0.2.0');
  const how2 = await ext.ensureServer({ ...opts, extensionDir: v2, extensionVersion: '0.2.0' });
  assert.ok(how2.command.startsWith(path.join(storage, 'server', '0.2.0-')), how2.command);
  const out2 = cp.spawnSync(how2.command, [...how2.args, '--version'], { encoding: 'utf8' });
  assert.match(out2.stdout, /tvl-lsp 0\.2\.0/);
  const left = fs.readdirSync(path.join(storage, 'server'));
  assert.deepStrictEqual(left, [path.basename(path.dirname(path.dirname(how2.command)))]);
});
