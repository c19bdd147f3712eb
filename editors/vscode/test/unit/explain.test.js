// Diagnostic codes link to their pages (the catalogue inside the server's package, fetched with
// the server's tvl-lsp.explain command). Runs the bundled client against a stand-in vscode module.
'use strict';
const test = require('node:test');
const assert = require('node:assert');
const path = require('path');
const { loadExtension } = require('./mock-vscode');

const bundle = path.resolve(__dirname, '..', '..', 'out', 'extension.js');

test("a tvl-lsp diagnostic's code becomes a link to its page; others are left alone", () => {
  const { ext } = loadExtension(bundle, {});
  const ours = { source: 'tvl-lsp', code: 'missing-arg', message: 'm' };
  const theirs = { source: 'xml', code: 'E1', message: 'm' };
  const done = { source: 'tvl-lsp', code: { value: 'x', target: 'y' }, message: 'm' };
  ext.linkCodes([ours, theirs, done]);
  assert.strictEqual(ours.code.value, 'missing-arg');
  assert.strictEqual(ours.code.target.scheme, 'tvl-lsp-explain');
  assert.strictEqual(ours.code.target.path, '/missing-arg.md');
  assert.strictEqual(theirs.code, 'E1');
  assert.deepStrictEqual(done.code, { value: 'x', target: 'y' });
});

test("a page is the server's answer; without one, it says why", async () => {
  const { ext } = loadExtension(bundle, {});
  const asked = [];
  const pages = new ext.ExplainPages(async (code) => { asked.push(code); return code === 'void-model' ? '## `void-model`\n' : undefined; });
  assert.strictEqual(await pages.provideTextDocumentContent(ext.explainUri('void-model')), '## `void-model`\n');
  assert.match(await pages.provideTextDocumentContent(ext.explainUri('nope')), /not running, or does not know this code/);
  assert.deepStrictEqual(asked, ['void-model', 'nope']);
});
