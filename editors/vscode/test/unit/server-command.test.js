// How the extension finds the server, and what it tells the user when it cannot.
// Runs the bundled client (out/extension.js) against a stand-in vscode module: npm run test:unit
'use strict';
const test = require('node:test');
const assert = require('node:assert');
const fs = require('fs');
const os = require('os');
const path = require('path');
const { loadExtension } = require('./mock-vscode');

const bundle = path.resolve(__dirname, '..', '..', 'out', 'extension.js');
const context = { subscriptions: [] };

function withPath(dirs, fn) {
  const saved = process.env.PATH;
  process.env.PATH = dirs.join(path.delimiter);
  try {
    return fn();
  } finally {
    process.env.PATH = saved;
  }
}

test('a missing server.path is reported, with the path, and no client starts', async () => {
  const { ext, shown } = loadExtension(bundle, { 'server.path': '/nonexistent/tvl-lsp' });
  const how = ext.serverCommand();
  assert.strictEqual(typeof how, 'string');
  assert.match(how, /tvl-lsp\.server\.path.*\/nonexistent\/tvl-lsp.*does not exist/);
  await ext.activate(context);
  assert.strictEqual(shown.errors.length, 1);
  assert.match(shown.errors[0], /does not exist/);
  assert.strictEqual(shown.context['tvl-lsp.running'], false);
  for (const id of ['tvl.include', 'tvl.exclude', 'tvl.reset', 'tvl.count', 'tvl.listProducts', 'tvl.generateConfigurations', 'tvl.explain']) {
    assert.ok(shown.commands.includes(id), id);
  }
});

test('no setting and nothing on PATH: the extension sets the server up itself (serverCommand is undefined)', () => {
  const { ext } = loadExtension(bundle, {});
  const how = withPath([fs.mkdtempSync(path.join(os.tmpdir(), 'empty-'))], () => ext.serverCommand());
  assert.strictEqual(how, undefined);
});

test('nothing configured and no wheel in the extension: the message says how to install and configure', async () => {
  const { ext, shown } = loadExtension(bundle, {});
  const ctx = {
    subscriptions: [],
    extensionPath: fs.mkdtempSync(path.join(os.tmpdir(), 'ext-')),
    globalStorageUri: { fsPath: fs.mkdtempSync(path.join(os.tmpdir(), 'storage-')) },
    extension: { packageJSON: { version: '0.1.0' } },
  };
  await withPath([fs.mkdtempSync(path.join(os.tmpdir(), 'empty-'))], () => ext.activate(ctx));
  assert.strictEqual(shown.errors.length, 1);
  assert.match(shown.errors[0], /not found on PATH/);
  assert.match(shown.errors[0], /tvl-lsp\.server\.path/);
  assert.match(shown.errors[0], /tvl-lsp\.server\.pythonPath/);
  assert.strictEqual(shown.context['tvl-lsp.running'], false);
});

test('tvl-lsp on PATH is used', () => {
  const dir = fs.mkdtempSync(path.join(os.tmpdir(), 'bin-'));
  const exe = path.join(dir, 'tvl-lsp');
  fs.writeFileSync(exe, '#!/bin/sh\n', { mode: 0o755 });
  const { ext } = loadExtension(bundle, {});
  const how = withPath([dir], () => ext.serverCommand());
  assert.deepStrictEqual({ command: how.command, args: how.args }, { command: exe, args: [] });
});

test('server.path wins over pythonPath, with ~ expanded', () => {
  const dir = fs.mkdtempSync(path.join(os.homedir(), '.tvl-lsp-test-'));
  try {
    const exe = path.join(dir, 'tvl-lsp');
    fs.writeFileSync(exe, '#!/bin/sh\n', { mode: 0o755 });
    const rel = '~/' + path.relative(os.homedir(), exe);
    const { ext } = loadExtension(bundle, { 'server.path': rel, 'server.pythonPath': '/usr/bin/python3' });
    const how = ext.serverCommand();
    assert.strictEqual(how.command, exe);
  } finally {
    fs.rmSync(dir, { recursive: true, force: true });
  }
});

test('pythonPath: an interpreter without tvl_lsp is refused with the pip command', () => {
  const python = process.env.TVL_TEST_BARE_PYTHON || '/usr/bin/python3';
  if (!fs.existsSync(python)) return;
  const { ext } = loadExtension(bundle, { 'server.pythonPath': python });
  const how = ext.serverCommand();
  assert.strictEqual(typeof how, 'string');
  assert.match(how, /cannot import tvl_lsp/);
  assert.match(how, /-m pip install/);
});

test('pythonPath: an interpreter with tvl_lsp starts `python -m tvl_lsp`', (t) => {
  const python = process.env.TVL_TEST_PYTHON;
  if (!python) {
    t.skip('TVL_TEST_PYTHON (an interpreter with tvl_lsp) not set');
    return;
  }
  const { ext } = loadExtension(bundle, { 'server.pythonPath': python });
  const how = ext.serverCommand();
  assert.deepStrictEqual({ command: how.command, args: how.args }, { command: python, args: ['-m', 'tvl_lsp'] });
});

test('the settings sent to the server have the server\'s shape', () => {
  const { ext } = loadExtension(bundle, { diagnostics: { 'missing-arg': 'off' }, 'count.timeBudget': 3, 'generate.folder': 'cfg', 'generate.limit': 7 });
  assert.deepStrictEqual(ext.serverSettings(), {
    diagnostics: { 'missing-arg': 'off' },
    count: { timeBudget: 3 },
    generate: { folder: 'cfg', limit: 7 },
  });
});
