// Small pieces of page furniture: toasts, modal dialogs, drop-down menus, links to source
// locations (an excerpt in the browser, the editor in VS Code).
import { el } from './format';
import type { Transport } from './transport';
import type { Excerpt, Location } from './types';

export interface Where {
  transport: Transport;
  roots: string[];
  model: () => string | undefined;
}

let where: Where | null = null;

export function setWhere(w: Where): void {
  where = w;
}

export function relative(path: string): string {
  for (const r of where?.roots ?? []) {
    const pre = r.endsWith('/') ? r : r + '/';
    if (path.startsWith(pre)) {
      return path.slice(pre.length);
    }
  }
  return path;
}

export function locText(loc: Location): string {
  return `${relative(loc.path)}:${loc.line + 1}:${loc.col + 1}`;
}

export function locLink(loc: Location | null, label?: string): HTMLElement {
  if (!loc) {
    return el('span', { class: 'muted' }, 'no location');
  }
  const a = el('a', { href: '#', class: 'loc', title: `show ${locText(loc)}` }, label ?? locText(loc));
  a.addEventListener('click', (ev) => {
    ev.preventDefault();
    void showLocation(loc);
  });
  return a;
}

/** A link that opens a whole (written) file: the editor in VS Code, an excerpt here. */
export function fileLink(path: string, label?: string): HTMLElement {
  const a = el('a', { href: '#', class: 'loc file', 'data-path': path, title: `open ${relative(path)}` }, label ?? relative(path));
  a.addEventListener('click', (ev) => {
    ev.preventDefault();
    void showLocation({ path, line: 0, col: 0, endLine: 0, endCol: 0 }, 400);
  });
  return a;
}

export async function showLocation(loc: Location, context = 4): Promise<void> {
  const w = where;
  if (!w) {
    return;
  }
  if (w.transport.reveal(loc)) {
    return;
  }
  try {
    const x = await w.transport.request<Excerpt>('excerpt', { model: w.model(), path: loc.path, line: loc.line, context });
    const pre = el('div', { class: 'excerpt' });
    x.lines.forEach((line, i) => {
      const n = x.start + i;
      pre.append(el('div', { class: n === loc.line && context < 50 ? 'line target' : 'line' },
        el('span', { class: 'ln' }, String(n + 1).padStart(4, ' ')), '  ', line));
    });
    modal(context < 50 ? `${x.relative}:${loc.line + 1}:${loc.col + 1}` : x.relative, pre);
  } catch (e) {
    toast(`Cannot show ${locText(loc)}: ${(e as Error).message}`, 'error');
  }
}

export function toast(content: string | Node, kind: 'info' | 'error' | 'refusal' = 'info', sticky = false): HTMLElement {
  const box = document.getElementById('toasts') as HTMLElement;
  const close = el('button', { class: 'close', title: 'dismiss', 'aria-label': 'dismiss' }, '×');
  const item = el('div', { class: `toast ${kind}`, role: kind === 'info' ? 'status' : 'alert' }, content, close);
  close.addEventListener('click', () => item.remove());
  box.append(item);
  if (!sticky) {
    setTimeout(() => item.remove(), kind === 'error' ? 12000 : 7000);
  }
  return item;
}

export function modal(title: string, body: Node, cls = ''): { close: () => void; box: HTMLElement } {
  document.querySelectorAll('.modal').forEach((m) => m.remove());
  const close = el('button', { class: 'close', title: 'close', 'aria-label': 'close' }, '×');
  const box = el('div', { class: `modal-box ${cls}` }, el('div', { class: 'modal-head' }, el('strong', {}, title), close), body);
  const dlg = el('div', { class: 'modal', role: 'dialog', 'aria-label': title }, box);
  const done = () => {
    dlg.remove();
    document.removeEventListener('keydown', esc);
  };
  function esc(ev: KeyboardEvent) {
    if (ev.key === 'Escape') {
      done();
    }
  }
  close.addEventListener('click', done);
  dlg.addEventListener('click', (ev) => ev.target === dlg && done());
  document.addEventListener('keydown', esc);
  document.body.append(dlg);
  return { close: done, box };
}

export interface MenuItem {
  id: string;
  label: string;
  title: string;
  run: () => void;
}

/** A button that opens a list of actions; `update(id, disabled, title)` later. */
export function menu(id: string, label: string, items: MenuItem[]): { root: HTMLElement; button: HTMLButtonElement;
  update: (item: string, disabled: boolean, title?: string) => void; } {
  const root = el('div', { class: 'menu', id: `${id}-menu` });
  const button = el('button', { id, 'aria-haspopup': 'true', 'aria-expanded': 'false' }, `${label} ▾`);
  const list = el('div', { class: 'menu-items', role: 'menu' });
  const buttons = new Map<string, HTMLButtonElement>();
  for (const it of items) {
    const b = el('button', { role: 'menuitem', 'data-action': it.id, title: it.title }, it.label);
    b.addEventListener('click', () => {
      root.classList.remove('open');
      button.setAttribute('aria-expanded', 'false');
      it.run();
    });
    buttons.set(it.id, b);
    list.append(b);
  }
  button.addEventListener('click', () => {
    document.querySelectorAll('.menu.open').forEach((m) => m !== root && m.classList.remove('open'));
    root.classList.toggle('open');
    button.setAttribute('aria-expanded', String(root.classList.contains('open')));
  });
  document.addEventListener('click', (ev) => {
    if (!root.contains(ev.target as Node)) {
      root.classList.remove('open');
    }
  });
  document.addEventListener('keydown', (ev) => {
    if (ev.key === 'Escape') {
      root.classList.remove('open');
    }
  });
  root.append(button, list);
  return {
    root, button,
    update: (item, disabled, title) => {
      const b = buttons.get(item);
      if (b) {
        b.disabled = disabled;
        if (title !== undefined) {
          b.title = title;
        }
      }
    },
  };
}

/** Tabs over panes: `[label, pane]`, the first shown. */
export function tabs(id: string, entries: [string, string, HTMLElement][]): { bar: HTMLElement; show: (key: string) => void;
  label: (key: string, text: string) => void; } {
  const bar = el('div', { class: 'tabs', role: 'tablist', id });
  const buttons = new Map<string, HTMLElement>();
  const show = (key: string) => {
    for (const [k, , pane] of entries) {
      pane.hidden = k !== key;
      buttons.get(k)?.setAttribute('aria-selected', String(k === key));
      buttons.get(k)?.classList.toggle('active', k === key);
    }
  };
  for (const [key, label] of entries) {
    const b = el('button', { role: 'tab', 'data-tab': key, id: `tab-${key}` }, label);
    b.addEventListener('click', () => show(key));
    buttons.set(key, b);
    bar.append(b);
  }
  show(entries[0][0]);
  return { bar, show, label: (key, text) => { const b = buttons.get(key); if (b) b.textContent = text; } };
}

export function sleep(ms: number): Promise<void> {
  return new Promise((resolve) => setTimeout(resolve, ms));
}

// ------------------------------------------------------------------ redraws and presses
// A click is a press and a release on the same element: a panel redrawn in between (an answer
// arriving -- counts, the problems, a decision's state -- replaces its buttons) turns the
// release into one on a new element, and the browser fires no click at all: the user's click
// is silently ignored. Panels that answers redraw go through redraw(): while a pointer is
// pressed the redraw waits for its release (the latest one per panel, run after the click).
let pressed = false;
let safety = 0;
const waiting = new Map<string, () => void>();

function flushRedraws(): void {
  pressed = false;
  clearTimeout(safety);
  const fns = [...waiting.values()];
  waiting.clear();
  fns.forEach((fn) => fn());
}

window.addEventListener('pointerdown', () => {
  pressed = true;
  clearTimeout(safety);
  safety = window.setTimeout(flushRedraws, 3000); // a release the page never saw (outside it)
}, true);
const released = () => {
  // the click is dispatched with the release: the waiting redraws run after it
  pressed = false;
  if (waiting.size) setTimeout(flushRedraws, 0);
};
window.addEventListener('pointerup', released, true);
window.addEventListener('pointercancel', released, true);
window.addEventListener('blur', released);

/** Redraw the panel `key` now, or after the pointer pressed on the page is released. */
export function redraw(key: string, fn: () => void): void {
  if (pressed) {
    waiting.set(key, fn);
    return;
  }
  waiting.delete(key);
  fn();
}
