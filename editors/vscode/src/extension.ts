// VS Code client for the tvl-lsp language server (TVL feature models and ROS launch files).
//
// The server is started as `tvl-lsp` (setting tvl-lsp.server.path, or found on PATH) or as
// `python -m tvl_lsp` (setting tvl-lsp.server.pythonPath); with neither, the extension sets it up
// itself in a private virtual environment from the wheel inside the .vsix (bootstrap.ts). It
// speaks LSP on stdio.
// The configurator and the generation of configuration launch files are server commands
// (workspace/executeCommand); the `tvl.*` commands below ask the user for their arguments.
import * as cp from 'child_process';
import * as fs from 'fs';
import * as os from 'os';
import * as path from 'path';
import * as vscode from 'vscode';
import {
  ExecuteCommandRequest,
  LanguageClient,
  LanguageClientOptions,
  ServerOptions,
  State,
} from 'vscode-languageclient/node';
import { bundledWheel, ensureServer, readyServer, ServerCommand } from './bootstrap';
// for the unit tests (test/unit), which load the bundle
export { bundledWheel, environmentKey, ensureServer, findPython, readyServer } from './bootstrap';
export { ExplainPages, explainUri, linkCodes } from './explain';

import { ConfiguratorPanel, MODEL_OR_LAUNCH } from './configurator';
import { EXPLAIN_SCHEME, ExplainPages, explainUri, linkCodes } from './explain';

const SECTION = 'tvl-lsp';
let client: LanguageClient | undefined;
let output: vscode.OutputChannel;
let status: vscode.StatusBarItem;

export async function activate(context: vscode.ExtensionContext): Promise<void> {
  output = vscode.window.createOutputChannel('TVL language server');
  status = vscode.window.createStatusBarItem(vscode.StatusBarAlignment.Left, 10);
  status.command = 'tvl.count';
  context.subscriptions.push(output, status);

  context.subscriptions.push(
    vscode.commands.registerCommand('tvl.restartServer', () => restart(context)),
    vscode.commands.registerCommand('tvl.showOutput', () => output.show()),
    vscode.commands.registerCommand('tvl.openConfigurator', () => openConfigurator(context)),
    vscode.commands.registerCommand('tvl.include', () => decide('tvl-lsp.include')),
    vscode.commands.registerCommand('tvl.exclude', () => decide('tvl-lsp.exclude')),
    vscode.commands.registerCommand('tvl.reset', () => reset()),
    vscode.commands.registerCommand('tvl.count', () => count()),
    vscode.commands.registerCommand('tvl.listProducts', () => listProducts()),
    vscode.commands.registerCommand('tvl.generateConfigurations', () => generate()),
    vscode.commands.registerCommand('tvl.explain', (code?: string) => explain(code)),
    vscode.workspace.registerTextDocumentContentProvider(
      EXPLAIN_SCHEME,
      new ExplainPages((code) => exec<{ markdown?: string }>('tvl-lsp.explain', [code]).then((r) => r?.markdown)),
    ),
    vscode.workspace.onDidChangeConfiguration((e) => {
      if (e.affectsConfiguration(`${SECTION}.server`)) {
        void vscode.window
          .showInformationMessage('The TVL server settings changed.', 'Restart the server')
          .then((pick) => pick && restart(context));
      }
    }),
  );
  await start(context);
}

export async function deactivate(): Promise<void> {
  if (client) {
    await client.stop();
    client = undefined;
  }
}

/** Expand `~` and `${workspaceFolder}` in a path setting. */
function expand(p: string): string {
  let s = p.trim();
  const folder = vscode.workspace.workspaceFolders?.[0]?.uri.fsPath ?? '';
  s = s.replace(/\$\{workspaceFolder\}/g, folder).replace(/\$\{userHome\}/g, os.homedir());
  if (s === '~' || s.startsWith('~/')) {
    s = path.join(os.homedir(), s.slice(1));
  }
  return s;
}

function onPath(exe: string): string | undefined {
  const dirs = (process.env.PATH ?? '').split(path.delimiter).filter((d) => d);
  const names = process.platform === 'win32' ? [exe + '.exe', exe + '.cmd', exe] : [exe];
  for (const d of dirs) {
    for (const n of names) {
      const full = path.join(d, n);
      try {
        fs.accessSync(full, fs.constants.X_OK);
        if (fs.statSync(full).isFile()) {
          return full;
        }
      } catch {
        // not here
      }
    }
  }
  return undefined;
}

/**
 * How the settings or PATH say to start the server, a message when a setting is wrong, or
 * undefined when nothing is configured and tvl-lsp is not on PATH (the extension then sets the
 * server up itself: bundledServer()).
 */
export function serverCommand(): ServerCommand | string | undefined {
  const cfg = vscode.workspace.getConfiguration(SECTION);
  const exe = expand(cfg.get<string>('server.path', ''));
  const python = expand(cfg.get<string>('server.pythonPath', ''));
  if (exe) {
    try {
      fs.accessSync(exe, fs.constants.X_OK);
    } catch {
      return `The tvl-lsp executable set in "tvl-lsp.server.path" (${exe}) does not exist or is not executable.`;
    }
    return { command: exe, args: [], description: exe };
  }
  if (python) {
    const probe = cp.spawnSync(python, ['-c', 'import tvl_lsp'], { encoding: 'utf8', timeout: 20000 });
    if (probe.error) {
      return `The Python interpreter set in "tvl-lsp.server.pythonPath" (${python}) cannot be run: ${probe.error.message}.`;
    }
    if (probe.status !== 0) {
      return `The Python interpreter ${python} cannot import tvl_lsp. Install it into that interpreter with "${python} -m pip install <path to the tvl-lsp repository>".`;
    }
    return { command: python, args: ['-m', 'tvl_lsp'], description: `${python} -m tvl_lsp` };
  }
  const found = onPath('tvl-lsp');
  if (found) {
    return { command: found, args: [], description: found };
  }
  return undefined;
}

export const NOT_FOUND =
  'The TVL language server (tvl-lsp) was not found on PATH and this build of the extension carries none to set up. Install it ("pip install <path to the tvl-lsp repository>"), then set "tvl-lsp.server.path" to the tvl-lsp executable or "tvl-lsp.server.pythonPath" to a Python interpreter that has it.';

/** Python interpreters the extension may create its private environment with, in order. */
export function setupPythonCandidates(): string[] {
  const own = expand(vscode.workspace.getConfiguration(SECTION).get<string>('server.setupPython', ''));
  if (own) {
    return [own]; // the user chose: no guessing
  }
  const out: string[] = [];
  const fromPythonExt = expand(vscode.workspace.getConfiguration('python').get<string>('defaultInterpreterPath', '') ?? '');
  if (fromPythonExt && fromPythonExt !== 'python') {
    out.push(fromPythonExt);
  }
  const names = process.platform === 'win32' ? ['python3', 'python'] : ['python3.13', 'python3.12', 'python3.11', 'python3.10', 'python3', 'python'];
  for (const n of names) {
    const p = onPath(n);
    if (p) {
      out.push(p);
    }
  }
  return out;
}

/** The server the extension sets up itself (bootstrap.ts), with a progress notification. */
async function bundledServer(context: vscode.ExtensionContext): Promise<ServerCommand | string> {
  const opts = {
    extensionDir: context.extensionPath,
    extensionVersion: String(context.extension?.packageJSON?.version ?? '0'),
    storageDir: context.globalStorageUri.fsPath,
  };
  let ready: ServerCommand | undefined;
  try {
    ready = readyServer(opts);
  } catch (err) {
    output.appendLine(`Checking the server set up by the extension: ${String(err)}`);
  }
  if (ready) {
    return ready;
  }
  if (!bundledWheel(opts.extensionDir)) {
    return NOT_FOUND;
  }
  return vscode.window.withProgress(
    { location: vscode.ProgressLocation.Notification, title: 'TVL: setting up the tvl-lsp language server', cancellable: false },
    async (progress) => {
      try {
        return await ensureServer({
          ...opts,
          pythonCandidates: setupPythonCandidates(),
          log: (l) => output.appendLine(l),
          progress: (message) => {
            output.appendLine(`[setup] ${message}`);
            progress.report({ message });
          },
        });
      } catch (err) {
        return `Setting up the TVL language server failed: ${err instanceof Error ? err.message : String(err)}`;
      }
    },
  );
}

/** The server's settings: everything in the tvl-lsp section but the client-only `server`. */
export function serverSettings(): Record<string, unknown> {
  const cfg = vscode.workspace.getConfiguration(SECTION);
  return {
    diagnostics: cfg.get('diagnostics', {}),
    count: { timeBudget: cfg.get('count.timeBudget', 10) },
    generate: { folder: cfg.get('generate.folder', ''), limit: cfg.get('generate.limit', 100) },
  };
}

async function start(context: vscode.ExtensionContext): Promise<void> {
  const how = serverCommand() ?? (await bundledServer(context));
  if (typeof how === 'string') {
    output.appendLine(how);
    void vscode.commands.executeCommand('setContext', 'tvl-lsp.running', false);
    // not awaited: activation must not wait for the user to answer
    void vscode.window.showErrorMessage(how, 'Retry', 'Open Settings', 'Show Output').then((pick) => {
      if (pick === 'Retry') {
        void restart(context);
      } else if (pick === 'Open Settings') {
        void vscode.commands.executeCommand('workbench.action.openSettings', 'tvl-lsp.server');
      } else if (pick === 'Show Output') {
        output.show();
      }
    });
    return;
  }
  output.appendLine(`Starting ${how.description}`);
  const serverOptions: ServerOptions = {
    run: { command: how.command, args: how.args },
    debug: { command: how.command, args: how.args },
  };
  const watcher = vscode.workspace.createFileSystemWatcher(
    '**/{*.tvl,*.launch,*.launch.xml,*.test,*.yaml,*.yml,package.xml,' +
      // the nodes' sources: what they publish and subscribe to is read from them (the graph)
      '*.cpp,*.cc,*.cxx,*.h,*.hpp,*.hh,*.py,CMakeLists.txt,setup.cfg}',
  );
  context.subscriptions.push(watcher);
  const clientOptions: LanguageClientOptions = {
    documentSelector: [
      { scheme: 'file', language: 'tvl' },
      { scheme: 'untitled', language: 'tvl' },
      { scheme: 'file', language: 'roslaunch' },
      { scheme: 'file', language: 'xml', pattern: '**/*{.launch,.launch.xml,_launch.xml,.test}' },
      // ROS 2 launch files in YAML (the yaml language keeps its highlighting)
      { scheme: 'file', language: 'yaml', pattern: '**/*{.launch.yaml,.launch.yml,_launch.yaml,_launch.yml}' },
      // the nodes' C++ and Python sources: editing one updates the graph and its findings; a
      // hover on a topic name says where the node runs and who is on the other end; among the
      // Python files, the ROS 2 launch files (*.launch.py, *_launch.py), analysed as launch files
      { scheme: 'file', language: 'cpp' },
      { scheme: 'file', language: 'c' },
      { scheme: 'file', language: 'python' },
    ],
    synchronize: { fileEvents: watcher },
    initializationOptions: { [SECTION]: serverSettings() },
    outputChannel: output,
    middleware: {
      // each diagnostic's code links to its page of the catalogue the server ships (explain.ts)
      handleDiagnostics: (uri, diagnostics, next) => next(uri, linkCodes(diagnostics)),
      provideDiagnostics: async (document, previousResultId, token, next) => {
        const report = await next(document, previousResultId, token);
        if (report && report.kind === 'full') {
          report.items = linkCodes(report.items);
        }
        return report;
      },
      workspace: {
        // Answer workspace/configuration for our section with the server's view of it.
        configuration: async (params, token, next) => {
          const result = await next(params, token);
          if (!Array.isArray(result)) {
            return result;
          }
          return params.items.map((item, i) => (item.section === SECTION ? serverSettings() : result[i]));
        },
      },
    },
  };
  client = new LanguageClient('tvl-lsp', 'TVL language server', serverOptions, clientOptions);
  client.onDidChangeState((e) => {
    void vscode.commands.executeCommand('setContext', 'tvl-lsp.running', e.newState === State.Running);
  });
  context.subscriptions.push(
    vscode.workspace.onDidChangeConfiguration((e) => {
      if (e.affectsConfiguration(SECTION) && client?.state === State.Running) {
        void client.sendNotification('workspace/didChangeConfiguration', { settings: { [SECTION]: serverSettings() } });
      }
    }),
  );
  try {
    await client.start();
  } catch (err) {
    const msg = `The TVL language server (${how.description}) failed to start: ${err instanceof Error ? err.message : String(err)}`;
    output.appendLine(msg);
    void vscode.window.showErrorMessage(msg, 'Show Output').then((p) => p && output.show());
  }
}

async function restart(context: vscode.ExtensionContext): Promise<void> {
  if (client) {
    try {
      await client.stop();
    } catch {
      // already stopped
    }
    client = undefined;
  }
  await start(context);
}

// ------------------------------------------------------------------ configurator

function running(): LanguageClient | undefined {
  if (!client || client.state !== State.Running) {
    void vscode.window.showErrorMessage('The TVL language server is not running (see "TVL: Show the language server\'s output").');
    return undefined;
  }
  return client;
}

/** The model or launch file the command is about: the active editor's file. */
function activeUri(): string | undefined {
  const doc = vscode.window.activeTextEditor?.document;
  if (!doc || !MODEL_OR_LAUNCH.test(doc.fileName)) {
    void vscode.window.showErrorMessage('Open a TVL model or a launch file paired with one first.');
    return undefined;
  }
  return doc.uri.toString();
}

async function exec<T>(command: string, args: unknown[]): Promise<T | undefined> {
  const c = running();
  if (!c) {
    return undefined;
  }
  try {
    return (await c.sendRequest(ExecuteCommandRequest.type, { command, arguments: args })) as T;
  } catch (err) {
    void vscode.window.showErrorMessage(`${command}: ${err instanceof Error ? err.message : String(err)}`);
    return undefined;
  }
}

interface Propagation {
  remaining?: number | string | null;
  remainingText?: string | null;
  total?: number | string | null;
  totalText?: string | null;
  decisions?: Record<string, boolean>;
  forced?: Record<string, boolean>;
  conflict?: unknown;
}

function showRemaining(r: Propagation | undefined, what: string): void {
  if (!r) {
    return;
  }
  const remaining = r.remainingText ?? (r.remaining != null ? String(r.remaining) : '?');
  const total = r.totalText ?? (r.total != null ? String(r.total) : undefined);
  status.text = `$(list-tree) TVL: ${remaining}${total ? ' of ' + total : ''} products`;
  status.tooltip = 'Products that remain under the configurator\'s decisions (click to recount)';
  status.show();
  const forced = r.forced ? Object.entries(r.forced).map(([f, v]) => (v ? f : '!' + f)) : [];
  void vscode.window.showInformationMessage(
    `${what}: ${remaining}${total ? ' of ' + total : ''} products remain` +
      (forced.length ? `; forced: ${forced.slice(0, 12).join(', ')}${forced.length > 12 ? ', …' : ''}` : ''),
  );
}

async function decide(command: 'tvl-lsp.include' | 'tvl-lsp.exclude'): Promise<void> {
  const uri = activeUri();
  if (!uri) {
    return;
  }
  const editor = vscode.window.activeTextEditor;
  let word = '';
  if (editor) {
    const range = editor.document.getWordRangeAtPosition(editor.selection.active, /[A-Za-z_][A-Za-z0-9_]*/);
    word = range ? editor.document.getText(range) : '';
  }
  const feature = await vscode.window.showInputBox({
    prompt: command === 'tvl-lsp.include' ? 'Feature to include' : 'Feature to exclude',
    value: word,
    validateInput: (v) => (/^[A-Za-z_][A-Za-z0-9_]*$/.test(v) ? undefined : 'a feature name'),
  });
  if (!feature) {
    return;
  }
  const r = await exec<Propagation>(command, [uri, feature]);
  showRemaining(r, `${command === 'tvl-lsp.include' ? 'Included' : 'Excluded'} ${feature}`);
  ConfiguratorPanel.refresh();
}

/** "TVL: Open configurator": the feature diagram, computation graph and problems of the active
 * model (or of the model paired with the active launch file) in a webview. */
function openConfigurator(context: vscode.ExtensionContext): void {
  const uri = activeUri();
  if (!uri || !running()) {
    return;
  }
  ConfiguratorPanel.show(context, () => (client && client.state === State.Running ? client : undefined), vscode.Uri.parse(uri));
}

async function reset(): Promise<void> {
  const uri = activeUri();
  if (uri) {
    showRemaining(await exec<Propagation>('tvl-lsp.reset', [uri]), 'Configuration reset');
    ConfiguratorPanel.refresh();
  }
}

async function count(): Promise<void> {
  const uri = activeUri();
  if (uri) {
    showRemaining(await exec<Propagation>('tvl-lsp.count', [uri]), 'Count');
  }
}

async function listProducts(): Promise<void> {
  const uri = activeUri();
  if (!uri) {
    return;
  }
  const r = await exec<{ products?: string[][]; remaining?: number; truncated?: boolean }>('tvl-lsp.listProducts', [uri, 200]);
  if (!r || !r.products) {
    return;
  }
  await vscode.window.showQuickPick(
    r.products.map((p, i) => ({ label: `#${i + 1}`, description: p.join(', ') })),
    { title: `${r.products.length}${r.truncated ? '+' : ''} remaining products`, matchOnDescription: true },
  );
}

async function generate(): Promise<void> {
  const uri = activeUri();
  if (!uri) {
    return;
  }
  const mode = await vscode.window.showQuickPick(
    [
      { label: 'all', detail: 'one configuration launch file per product (up to tvl-lsp.generate.limit)' },
      { label: 'completions', detail: 'every completion of the configurator\'s current decisions' },
      { label: 'one', detail: 'one product that satisfies the current decisions' },
    ],
    { title: 'Generate configuration launch files' },
  );
  if (!mode) {
    return;
  }
  const cfg = vscode.workspace.getConfiguration(SECTION);
  const opts: Record<string, unknown> = { uri, mode: mode.label };
  const folder = cfg.get<string>('generate.folder', '');
  if (folder) {
    opts.folder = folder;
  }
  const r = await exec<{ files?: string[]; truncated?: boolean; applied?: boolean; message?: string }>(
    'tvl-lsp.generateConfigurations',
    [opts],
  );
  if (!r || !r.files) {
    return;
  }
  if (!r.files.length && r.message) {
    void vscode.window.showInformationMessage(`TVL: ${r.message}`);
    return;
  }
  // The server creates the files through a workspace edit: VS Code then holds their text in
  // unsaved editors. Generating means writing them, so save each one.
  const unsaved: string[] = [];
  for (const f of r.files) {
    const target = f.includes('://') ? vscode.Uri.parse(f) : vscode.Uri.file(f);
    const doc = vscode.workspace.textDocuments.find((d) => d.uri.toString() === target.toString());
    if (doc?.isDirty && !(await doc.save())) {
      unsaved.push(path.basename(target.fsPath));
    }
  }
  if (unsaved.length) {
    void vscode.window.showWarningMessage(`TVL: could not save ${unsaved.join(', ')}`);
  }
  const pick = await vscode.window.showInformationMessage(
    `Generated ${r.files.length} configuration launch file(s)${r.truncated ? ' (limit reached)' : ''}.`,
    ...(r.files.length ? ['Open the first'] : []),
  );
  if (pick && r.files.length) {
    const f = r.files[0];
    const target = f.includes('://') ? vscode.Uri.parse(f) : vscode.Uri.file(f);
    await vscode.window.showTextDocument(target);
  }
}

// ------------------------------------------------------------------ diagnostic codes

/** "TVL: Explain a diagnostic code": a code's page (what it means, an example, the fix) from the
 * diagnostics catalogue inside the server's package, in the Markdown preview. */
async function explain(code?: string): Promise<void> {
  if (!code) {
    const list = await exec<{ codes?: { code: string; severity: string; summary: string }[] }>('tvl-lsp.explain', []);
    if (!list?.codes) {
      return;
    }
    const pick = await vscode.window.showQuickPick(
      list.codes.map((c) => ({ label: c.code, description: c.severity, detail: c.summary })),
      { title: 'Explain a diagnostic code', matchOnDescription: true, matchOnDetail: true },
    );
    if (!pick) {
      return;
    }
    code = pick.label;
  }
  await vscode.commands.executeCommand('markdown.showPreview', explainUri(code));
}
