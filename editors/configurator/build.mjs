// Builds the configurator's web UI into the Python package (tvl_lsp/ui/static/), where it is
// committed: `pip install` alone then serves it, without Node. BUILD-INFO.json records a hash
// of every input, so tests/test_ui_bundle.py can tell when the bundle is older than its sources.
//   node build.mjs           build
//   node build.mjs --check   exit 1 if the committed bundle does not match a fresh build
import { build } from 'esbuild';
import { createHash } from 'node:crypto';
import { copyFileSync, mkdirSync, mkdtempSync, readdirSync, readFileSync, rmSync, writeFileSync } from 'node:fs';
import { tmpdir } from 'node:os';
import { dirname, join, relative } from 'node:path';
import { fileURLToPath } from 'node:url';

const here = dirname(fileURLToPath(import.meta.url));
const target = join(here, '..', '..', 'tvl_lsp', 'ui', 'static');
const check = process.argv.includes('--check');

/** The inputs: sources, build script, lock file (sorted, as the Python test lists them). */
export function inputs() {
  const out = [];
  const walk = (d) => {
    for (const n of readdirSync(d, { withFileTypes: true })) {
      const p = join(d, n.name);
      if (n.isDirectory()) walk(p);
      else out.push(p);
    }
  };
  walk(join(here, 'src'));
  out.push(join(here, 'build.mjs'), join(here, 'package.json'), join(here, 'package-lock.json'));
  return out.map((p) => relative(here, p).split('\\').join('/')).sort();
}

function sourceHash() {
  const h = createHash('sha256');
  for (const rel of inputs()) {
    h.update(rel + '\0');
    h.update(readFileSync(join(here, rel)).toString('utf8').replace(/\r\n/g, '\n'));
    h.update('\0');
  }
  return h.digest('hex');
}

/** The licences of the bundled packages (d3 modules: ISC; elkjs: EPL-2.0). */
function notices() {
  const parts = ['Third-party software bundled in app.js and elk-worker.js:\n'];
  const nm = join(here, 'node_modules');
  const names = readdirSync(nm).filter((n) => n.startsWith('d3-') || n === 'elkjs').sort();
  for (const n of names) {
    const pkg = JSON.parse(readFileSync(join(nm, n, 'package.json'), 'utf8'));
    const lic = readdirSync(join(nm, n)).find((f) => /^licen[sc]e/i.test(f));
    parts.push(`\n==== ${n} ${pkg.version} (${pkg.license}) ${pkg.homepage ?? ''}\n`);
    if (lic) parts.push(readFileSync(join(nm, n, lic), 'utf8').replace(/\r\n/g, '\n'));
  }
  return parts.join('');
}

async function buildInto(dir) {
  mkdirSync(dir, { recursive: true });
  await build({
    entryPoints: [join(here, 'src', 'main.ts')],
    bundle: true,
    format: 'iife',
    target: 'es2020',
    platform: 'browser',
    minify: true,
    legalComments: 'linked',
    charset: 'utf8',
    outfile: join(dir, 'app.js'),
    logLevel: 'warning',
  });
  copyFileSync(join(here, 'src', 'index.html'), join(dir, 'index.html'));
  copyFileSync(join(here, 'src', 'app.css'), join(dir, 'app.css'));
  copyFileSync(join(here, 'node_modules', 'elkjs', 'lib', 'elk-worker.min.js'), join(dir, 'elk-worker.js'));
  writeFileSync(join(dir, 'THIRD-PARTY-NOTICES.txt'), notices());
  const files = {};
  for (const n of readdirSync(dir).sort()) {
    if (n !== 'BUILD-INFO.json') {
      files[n] = createHash('sha256').update(readFileSync(join(dir, n))).digest('hex');
    }
  }
  const info = { sources: sourceHash(), inputs: inputs(), files };
  writeFileSync(join(dir, 'BUILD-INFO.json'), JSON.stringify(info, null, 2) + '\n');
}

if (check) {
  const tmp = mkdtempSync(join(tmpdir(), 'tvl-ui-'));
  try {
    await buildInto(tmp);
    const stale = [];
    for (const n of readdirSync(tmp)) {
      let committed = null;
      try {
        committed = readFileSync(join(target, n));
      } catch {}
      if (!committed || !committed.equals(readFileSync(join(tmp, n)))) stale.push(n);
    }
    if (stale.length) {
      console.error(`tvl_lsp/ui/static is out of date (${stale.join(', ')}): run "npm run build" in editors/configurator and commit it`);
      process.exit(1);
    }
    console.log('tvl_lsp/ui/static is up to date with editors/configurator');
  } finally {
    rmSync(tmp, { recursive: true, force: true });
  }
} else {
  await buildInto(target);
  console.log(`built ${relative(process.cwd(), target)}`);
}
