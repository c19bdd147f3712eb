// A stand-in for the `vscode` module, enough to load the bundled extension and call its
// activation and server-resolution code outside VS Code. Records the messages shown.
'use strict';
const Module = require('module');

function make(settings) {
  const shown = { errors: [], infos: [], commands: [], context: {} };
  const noop = () => {};
  const disposable = { dispose: noop };
  const handler = {
    get(target, prop) {
      if (prop in target) return target[prop];
      // anything else: a constructible, callable no-op whose properties are no-ops too
      const f = function () { return new Proxy({}, handler); };
      return new Proxy(f, { get: (t, p) => (p === 'prototype' ? {} : handler.get({}, p)), construct: () => new Proxy({}, handler) });
    },
  };
  const config = {
    get: (key, dflt) => (key in settings ? settings[key] : dflt),
    has: (key) => key in settings,
  };
  const vscode = {
    StatusBarAlignment: { Left: 1, Right: 2 },
    Uri: {
      parse: (s) => ({ toString: () => s, fsPath: s }),
      file: (s) => ({ toString: () => 'file://' + s, fsPath: s }),
      from: (c) => ({ ...c, toString: () => `${c.scheme}:${c.path}` }),
    },
    workspace: {
      workspaceFolders: [{ uri: { fsPath: '/ws' } }],
      getConfiguration: () => config,
      onDidChangeConfiguration: () => disposable,
      registerTextDocumentContentProvider: () => disposable,
      createFileSystemWatcher: () => ({ dispose: noop, onDidCreate: () => disposable, onDidChange: () => disposable, onDidDelete: () => disposable }),
    },
    window: {
      createOutputChannel: () => ({ appendLine: noop, append: noop, show: noop, dispose: noop, clear: noop }),
      createStatusBarItem: () => ({ show: noop, hide: noop, dispose: noop }),
      showErrorMessage: (msg) => { shown.errors.push(msg); return Promise.resolve(undefined); },
      showInformationMessage: (msg) => { shown.infos.push(msg); return Promise.resolve(undefined); },
    },
    commands: {
      registerCommand: (id) => { shown.commands.push(id); return disposable; },
      executeCommand: (id, key, value) => { if (id === 'setContext') shown.context[key] = value; return Promise.resolve(); },
    },
  };
  return { vscode: new Proxy(vscode, handler), shown };
}

/** Load out/extension.js afresh with `settings` as the tvl-lsp configuration. */
function loadExtension(bundle, settings) {
  const { vscode, shown } = make(settings);
  const origResolve = Module._resolveFilename;
  const origLoad = Module._load;
  Module._load = function (request, ...rest) {
    if (request === 'vscode') return vscode;
    return origLoad.call(this, request, ...rest);
  };
  try {
    delete require.cache[require.resolve(bundle)];
    const ext = require(bundle);
    return { ext, shown };
  } finally {
    Module._load = origLoad;
    Module._resolveFilename = origResolve;
  }
}

module.exports = { loadExtension };
