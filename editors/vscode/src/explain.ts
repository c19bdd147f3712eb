// Diagnostic codes as links to their pages. The pages are the diagnostics catalogue inside the
// server's package (tvl_lsp/data/diagnostics.md), fetched with the server's `tvl-lsp.explain`
// command: the extension shows the version of the pages that matches the server it runs.
import * as vscode from 'vscode';

export const EXPLAIN_SCHEME = 'tvl-lsp-explain';

/** tvl-lsp-explain:/CODE.md, a read-only Markdown document. */
export function explainUri(code: string): vscode.Uri {
  return vscode.Uri.from({ scheme: EXPLAIN_SCHEME, path: `/${code}.md` });
}

/** Give each tvl-lsp diagnostic's code a target: its page (the Problems panel and the hover
 * show the code as a link). */
export function linkCodes(diagnostics: vscode.Diagnostic[]): vscode.Diagnostic[] {
  for (const d of diagnostics) {
    if (d.source === 'tvl-lsp' && (typeof d.code === 'string' || typeof d.code === 'number')) {
      d.code = { value: d.code, target: explainUri(String(d.code)) };
    }
  }
  return diagnostics;
}

export class ExplainPages implements vscode.TextDocumentContentProvider {
  constructor(private readonly fetch: (code: string) => Promise<string | undefined>) {}

  async provideTextDocumentContent(uri: vscode.Uri): Promise<string> {
    const code = uri.path.replace(/^\//, '').replace(/\.md$/, '');
    const page = await this.fetch(code);
    return page ?? `# ${code}\n\nThe TVL language server is not running, or does not know this code.\n`;
  }
}
