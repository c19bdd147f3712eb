// "TVL: Open configurator": the configurator's web UI (the same bundle `tvl-lsp ui` serves,
// tvl_lsp/ui/static, copied to out/configurator) in a webview panel. The page posts its
// requests; they go to the language server's `tvl-lsp.configurator` command for the active
// model or generic launch file, and the answers come back. Locations open in the editor.
import * as vscode from 'vscode';
import { ExecuteCommandRequest, LanguageClient } from 'vscode-languageclient/node';

/** Models and the launch files the server analyses (ROS 1 XML, ROS 2 XML / YAML / Python). */
export const MODEL_OR_LAUNCH = /\.(tvl|uvl|dimacs|launch|test)$|[._]launch\.(xml|yaml|yml|py)$/i;

export class ConfiguratorPanel {
  static current: ConfiguratorPanel | undefined;
  private readonly disposables: vscode.Disposable[] = [];

  static show(context: vscode.ExtensionContext, client: () => LanguageClient | undefined, uri: vscode.Uri): void {
    if (ConfiguratorPanel.current) {
      ConfiguratorPanel.current.panel.reveal(vscode.ViewColumn.Beside);
      ConfiguratorPanel.current.follow(uri);
      return;
    }
    const panel = vscode.window.createWebviewPanel('tvlConfigurator', 'TVL configurator', vscode.ViewColumn.Beside, {
      enableScripts: true,
      retainContextWhenHidden: true,
      localResourceRoots: [vscode.Uri.joinPath(context.extensionUri, 'out', 'configurator')],
    });
    ConfiguratorPanel.current = new ConfiguratorPanel(context, panel, client, uri);
  }

  private constructor(
    private readonly context: vscode.ExtensionContext,
    readonly panel: vscode.WebviewPanel,
    private readonly client: () => LanguageClient | undefined,
    private uri: vscode.Uri,
  ) {
    panel.webview.html = this.html();
    this.title();
    panel.onDidDispose(() => this.dispose(), null, this.disposables);
    panel.webview.onDidReceiveMessage((m) => void this.onMessage(m), null, this.disposables);
    // follow the active model / generic launch file
    vscode.window.onDidChangeActiveTextEditor((e) => {
      if (e && e.document.uri.scheme === 'file' && MODEL_OR_LAUNCH.test(e.document.fileName)) {
        this.follow(e.document.uri);
      }
    }, null, this.disposables);
  }

  /** Show another model (or launch file); a refresh of the same one otherwise. */
  follow(uri: vscode.Uri): void {
    const reload = uri.toString() !== this.uri.toString();
    this.uri = uri;
    this.title();
    void this.panel.webview.postMessage({ type: 'refresh', reload });
  }

  /** The decisions changed elsewhere (the palette's include / exclude / reset). */
  static refresh(): void {
    void ConfiguratorPanel.current?.panel.webview.postMessage({ type: 'refresh', reload: false });
  }

  private title(): void {
    this.panel.title = `TVL configurator: ${this.uri.path.split('/').pop()}`;
  }

  private async onMessage(m: { type?: string; id?: number; op?: string; params?: unknown; location?: Loc }): Promise<void> {
    if (m.type === 'request' && typeof m.id === 'number') {
      const c = this.client();
      if (!c) {
        void this.panel.webview.postMessage({ type: 'response', id: m.id, error: 'The TVL language server is not running.' });
        return;
      }
      try {
        const result = await c.sendRequest(ExecuteCommandRequest.type, {
          command: 'tvl-lsp.configurator',
          arguments: [this.uri.toString(), m.op, m.params ?? {}],
        });
        void this.panel.webview.postMessage({ type: 'response', id: m.id, result });
        if (m.op === 'generate') {
          const files = (result as { written?: string[] })?.written ?? [];
          if (files.length === 1) {
            void vscode.window.showTextDocument(vscode.Uri.file(files[0]), { viewColumn: vscode.ViewColumn.One, preview: true });
          }
        }
      } catch (err) {
        void this.panel.webview.postMessage({ type: 'response', id: m.id, error: err instanceof Error ? err.message : String(err) });
      }
    } else if (m.type === 'reveal' && m.location) {
      const l = m.location;
      const range = new vscode.Range(l.line, l.col, l.endLine, l.endCol);
      const doc = await vscode.workspace.openTextDocument(vscode.Uri.file(l.path));
      await vscode.window.showTextDocument(doc, { viewColumn: vscode.ViewColumn.One, selection: range });
    }
  }

  private html(): string {
    const w = this.panel.webview;
    const base = vscode.Uri.joinPath(this.context.extensionUri, 'out', 'configurator');
    const js = w.asWebviewUri(vscode.Uri.joinPath(base, 'app.js'));
    const css = w.asWebviewUri(vscode.Uri.joinPath(base, 'app.css'));
    const worker = w.asWebviewUri(vscode.Uri.joinPath(base, 'elk-worker.js'));
    const nonce = [...Array(32)].map(() => Math.floor(Math.random() * 36).toString(36)).join('');
    const csp = [
      "default-src 'none'",
      `script-src 'nonce-${nonce}'`,
      `style-src ${w.cspSource}`,
      `img-src ${w.cspSource} data:`,
      `connect-src ${w.cspSource}`,
      'worker-src blob:',
    ].join('; ');
    return `<!doctype html>
<html lang="en">
<head>
<meta charset="utf-8">
<meta http-equiv="Content-Security-Policy" content="${csp}">
<meta name="viewport" content="width=device-width, initial-scale=1">
<meta name="tvl-elk-worker" content="${worker}">
<link rel="stylesheet" href="${css}">
<title>TVL configurator</title>
</head>
<body>
<div id="app" class="loading">Loading the configurator…</div>
<script nonce="${nonce}" src="${js}"></script>
</body>
</html>`;
  }

  private dispose(): void {
    ConfiguratorPanel.current = undefined;
    this.disposables.forEach((d) => d.dispose());
    // the page's background work (compiling a big model for its counts) ends with the panel
    const c = this.client();
    if (c) {
      void c.sendRequest(ExecuteCommandRequest.type, {
        command: 'tvl-lsp.configurator',
        arguments: [this.uri.toString(), 'close', {}],
      }).then(undefined, () => undefined);
    }
  }
}

interface Loc {
  path: string;
  line: number;
  col: number;
  endLine: number;
  endCol: number;
}
