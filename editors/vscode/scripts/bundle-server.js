// Builds the tvl-lsp wheel from this repository into server/, so that the .vsix carries the
// server it sets up on first use (src/bootstrap.ts). Run by `npm run build` (and so by
// `vsce package`). The Python that builds it: $TVL_PYTHON, else the repository's .venv, else
// python3 on PATH; it needs pip (which fetches setuptools for the build, as for any pip install).
'use strict';
const cp = require('child_process');
const fs = require('fs');
const path = require('path');

const repo = path.resolve(__dirname, '..', '..', '..');
const out = path.resolve(__dirname, '..', 'server');
const venv = path.join(repo, '.venv', process.platform === 'win32' ? 'Scripts/python.exe' : 'bin/python');
const python = process.env.TVL_PYTHON || (fs.existsSync(venv) ? venv : 'python3');

fs.rmSync(out, { recursive: true, force: true });
fs.mkdirSync(out, { recursive: true });
const r = cp.spawnSync(python, ['-m', 'pip', 'wheel', '--no-deps', '--disable-pip-version-check', '-q', '-w', out, repo], {
  stdio: ['ignore', 'inherit', 'inherit'],
});
if (r.error || r.status !== 0) {
  console.error(`bundle-server: "${python} -m pip wheel ${repo}" failed${r.error ? ': ' + r.error.message : ''}`);
  process.exit(1);
}
const wheels = fs.readdirSync(out).filter((n) => /^tvl_lsp-.*-py3-none-any\.whl$/.test(n));
if (wheels.length !== 1) {
  console.error(`bundle-server: expected one tvl_lsp wheel in ${out}, found ${fs.readdirSync(out).join(', ') || 'nothing'}`);
  process.exit(1);
}
const buf = fs.readFileSync(path.join(out, wheels[0]));
// the diagnostics catalogue: the server's hovers and the extension's explain pages read it
for (const need of ['tvl_lsp/__main__.py', 'tvl_lsp/grammars/tvl.lark', 'tvl_lsp/data/diagnostics.md']) {
  if (buf.indexOf(Buffer.from(need)) < 0) {
    console.error(`bundle-server: ${wheels[0]} lacks ${need}`);
    process.exit(1);
  }
}
console.log(`bundled ${wheels[0]} (${buf.length} bytes) from ${repo}`);
