// How the UI talks to its host: HTTP to `tvl-lsp ui` in a browser, or messages to the VS Code
// extension in a webview (which forwards them to the language server's tvl-lsp.configurator
// command). Both answer the same requests (tvl_lsp/configurator/api.py).
import type { Location } from './types';

export interface Transport {
  readonly kind: 'http' | 'vscode';
  request<T>(op: string, params?: Record<string, unknown>): Promise<T>;
  /** Show a location in the editor; false when the host cannot (the UI shows an excerpt). */
  reveal(loc: Location): boolean;
  /** Called by the host when something changed outside the UI (palette commands, edits). */
  onRefresh(fn: (reload: boolean) => void): void;
  /** A Web Worker running ELK (elk-worker.js, shipped beside app.js). */
  layoutWorker(): Promise<Worker>;
}

export class RequestError extends Error {
  constructor(message: string, readonly status?: number) {
    super(message);
  }
}

class HttpTransport implements Transport {
  readonly kind = 'http' as const;
  constructor(private token: string) {}

  async request<T>(op: string, params: Record<string, unknown> = {}): Promise<T> {
    let res: Response;
    try {
      res = await fetch(`api/${op}`, {
        method: 'POST',
        headers: { 'Content-Type': 'application/json', 'X-TVL-Token': this.token },
        body: JSON.stringify(params),
        cache: 'no-store',
      });
    } catch (e) {
      throw new RequestError('The tvl-lsp ui server does not answer (was it stopped?).');
    }
    const text = await res.text();
    let body: unknown = null;
    try {
      body = JSON.parse(text);
    } catch {
      body = { error: text.trim() };
    }
    if (!res.ok) {
      const msg = (body as { error?: string })?.error ?? `HTTP ${res.status}`;
      throw new RequestError(msg, res.status);
    }
    return body as T;
  }

  reveal(): boolean {
    return false;
  }

  async layoutWorker(): Promise<Worker> {
    return new Worker(`static/elk-worker.js?token=${encodeURIComponent(this.token)}`);
  }

  onRefresh(): void {
    // the browser host has no other client changing the decisions
  }
}

interface VsCodeApi {
  postMessage(msg: unknown): void;
}

declare function acquireVsCodeApi(): VsCodeApi;

class VsCodeTransport implements Transport {
  readonly kind = 'vscode' as const;
  private next = 1;
  private pending = new Map<number, { resolve: (v: unknown) => void; reject: (e: Error) => void }>();
  private refreshers: ((reload: boolean) => void)[] = [];

  constructor(private api: VsCodeApi) {
    window.addEventListener('message', (ev: MessageEvent) => {
      const m = ev.data as { type?: string; id?: number; result?: unknown; error?: string; reload?: boolean };
      if (m?.type === 'response' && typeof m.id === 'number') {
        const p = this.pending.get(m.id);
        if (p) {
          this.pending.delete(m.id);
          if (m.error !== undefined) {
            p.reject(new RequestError(m.error));
          } else {
            p.resolve(m.result);
          }
        }
      } else if (m?.type === 'refresh') {
        this.refreshers.forEach((fn) => fn(Boolean(m.reload)));
      }
    });
  }

  request<T>(op: string, params: Record<string, unknown> = {}): Promise<T> {
    const id = this.next++;
    return new Promise<T>((resolve, reject) => {
      this.pending.set(id, { resolve: resolve as (v: unknown) => void, reject });
      this.api.postMessage({ type: 'request', id, op, params });
    });
  }

  reveal(loc: Location): boolean {
    this.api.postMessage({ type: 'reveal', location: loc });
    return true;
  }

  onRefresh(fn: (reload: boolean) => void): void {
    this.refreshers.push(fn);
  }

  async layoutWorker(): Promise<Worker> {
    // a webview's resources are on another origin than the page: start the worker from a blob
    const meta = document.querySelector('meta[name="tvl-elk-worker"]') as HTMLMetaElement | null;
    if (!meta?.content) {
      throw new Error('the layout worker is missing');
    }
    const code = await (await fetch(meta.content)).text();
    return new Worker(URL.createObjectURL(new Blob([code], { type: 'text/javascript' })));
  }
}

export function makeTransport(): Transport {
  if (typeof acquireVsCodeApi === 'function') {
    return new VsCodeTransport(acquireVsCodeApi());
  }
  const meta = document.querySelector('meta[name="tvl-token"]') as HTMLMetaElement | null;
  return new HttpTransport(meta?.content ?? new URLSearchParams(location.search).get('token') ?? '');
}
