"""Document synchronisation, settings, workspace folders and watched files."""

from __future__ import annotations

import asyncio
import logging

from lsprotocol import types

from ..convert import apply_change_at, path_to_uri, uri_to_path

log = logging.getLogger("tvl_lsp.server")


def register(ls) -> None:
    from ..documents import Document, text_diff

    @ls.feature(types.INITIALIZE)
    def initialize(ls, params: types.InitializeParams):
        ls.settings.update(params.initialization_options or {})
        roots = []
        for f in params.workspace_folders or []:
            roots.append(uri_to_path(f.uri))
        if not roots and params.root_uri:
            roots.append(uri_to_path(params.root_uri))
        elif not roots and params.root_path:
            roots.append(params.root_path)
        ls.roots = roots

    @ls.feature(types.INITIALIZED)
    async def initialized(ls, params):
        ls.warm_up()
        from ..workers import _WATCHDOG
        for hb in _WATCHDOG:
            asyncio.ensure_future(hb())
        await _pull_configuration(ls)
        if ls.cap("workspace.did_change_watched_files.dynamic_registration", False):
            try:
                await ls.client_register_capability_async(types.RegistrationParams(registrations=[
                    types.Registration(
                        id="tvl-lsp-watch", method=types.WORKSPACE_DID_CHANGE_WATCHED_FILES,
                        register_options=types.DidChangeWatchedFilesRegistrationOptions(watchers=[
                            types.FileSystemWatcher(glob_pattern=g) for g in
                            ("**/*.tvl", "**/*.uvl", "**/*.dimacs", "**/*.launch", "**/*.launch.xml", "**/*.test",
                             "**/*_launch.xml",
                             "**/package.xml", "**/*.yaml", "**/*.yml",
                             # the nodes' sources (the computation graph reads them), and the ROS 2
                             # Python launch files among them
                             "**/*.{cpp,cc,cxx,h,hpp,hh,py}", "**/CMakeLists.txt", "**/setup.cfg")]))]))
            except Exception:  # the client said no: fine
                log.debug("watched files registration refused")

    @ls.feature(types.SHUTDOWN)
    def shutdown(ls, params=None):
        for t in list(ls._full_tasks.values()):
            t.cancel()
        ls.restart_proc_pool()  # kill the worker processes: exit must not wait for a count
        ls.restart_check_pool()
        ls.stop_background_pool()
        ls.executor.shutdown(wait=False, cancel_futures=True)

    @ls.feature(types.EXIT)
    def exit_(ls, params=None):
        shutdown(ls)  # (again, if the client skipped ``shutdown``): exit must not wait for a count

    @ls.feature(types.WORKSPACE_DID_CHANGE_CONFIGURATION)
    async def did_change_configuration(ls, params: types.DidChangeConfigurationParams):
        if isinstance(params.settings, dict) and params.settings:
            ls.settings.update(params.settings)
        else:
            await _pull_configuration(ls)
        ls.recheck_all()

    @ls.feature(types.WORKSPACE_DID_CHANGE_WORKSPACE_FOLDERS)
    def did_change_folders(ls, params: types.DidChangeWorkspaceFoldersParams):
        removed = {uri_to_path(f.uri) for f in params.event.removed or []}
        ls.epoch += 1
        ls.roots = [r for r in ls.roots if r not in removed]
        for f in params.event.added or []:
            p = uri_to_path(f.uri)
            if p not in ls.roots:
                ls.roots.append(p)
        ls.recheck_all()

    @ls.feature(types.WORKSPACE_DID_CHANGE_WATCHED_FILES)
    def did_change_watched(ls, params: types.DidChangeWatchedFilesParams):
        changed = set()
        if any(ev.type != types.FileChangeType.Changed for ev in params.changes) or any(
                uri_to_path(ev.uri).endswith(("package.xml", ".yaml", ".yml")) for ev in params.changes):
            ls.epoch += 1  # files appeared / vanished, or pairings / packages changed
        for ev in params.changes:
            p = uri_to_path(ev.uri)
            ls.disk_cache.pop(p, None)
            changed.add(p)
        # project files or manifests change pairings and packages: re-check everything
        if any(p.endswith(("package.xml", ".yaml", ".yml")) for p in changed):
            ls.recheck_all()
            return
        for p in changed:
            if ls.docs.get(path_to_uri(p)) is None:  # open documents win over disk
                ls.recheck_dependents(p)

    @ls.feature(types.TEXT_DOCUMENT_DID_OPEN)
    def did_open(ls, params: types.DidOpenTextDocumentParams):
        td = params.text_document
        ls.docs[td.uri] = Document(td.uri, td.text, td.version)
        ls.schedule(td.uri)
        ls.recheck_dependents(uri_to_path(td.uri))

    @ls.feature(types.TEXT_DOCUMENT_DID_CHANGE)
    def did_change(ls, params: types.DidChangeTextDocumentParams):
        uri = params.text_document.uri
        doc = ls.docs.get(uri)
        if doc is None:
            return
        text = doc.text
        enc = ls.encoding
        edits = []  # (where each change was: older results are mapped onto the new text)
        for ch in params.content_changes:
            rng = getattr(ch, "range", None)
            try:
                new, at = apply_change_at(text, rng, ch.text, enc)
                edits.append(at if at is not None else text_diff(text, new))
                text = new
            except Exception:  # never let a bad change kill the server
                log.exception("bad change ignored")
        doc.set_text(text, params.text_document.version, edits)
        if doc.path.endswith(("package.xml", ".yaml", ".yml")):
            ls.epoch += 1
        ls.schedule(uri)
        ls.recheck_dependents(doc.path)

    @ls.feature(types.TEXT_DOCUMENT_DID_SAVE)
    def did_save(ls, params: types.DidSaveTextDocumentParams):
        ls.disk_cache.pop(uri_to_path(params.text_document.uri), None)

    @ls.feature(types.TEXT_DOCUMENT_DID_CLOSE)
    def did_close(ls, params: types.DidCloseTextDocumentParams):
        uri = params.text_document.uri
        doc = ls.docs.pop(uri, None)
        for t in (ls._full_tasks.pop(uri, None),):
            if t is not None and not t.done():
                t.cancel()
        ls._generation.pop(uri, None)
        ls._check_running.pop(uri, None)
        ls.published.pop(uri, None)
        if doc is not None:
            ls.parsed_cache.pop(doc.path, None)
            ls.good_parsed.pop(doc.path, None)
        ls.clear(uri)
        if doc is not None:
            ls.recheck_dependents(doc.path)  # they now see the disk text


async def _pull_configuration(ls) -> None:
    if not ls.cap("workspace.configuration", False):
        return
    try:
        res = await asyncio.wait_for(ls.workspace_configuration_async(
            types.ConfigurationParams(items=[types.ConfigurationItem(section="tvl-lsp")])), 5)
    except Exception:
        return
    if res and isinstance(res[0], dict):
        ls.settings.update(res[0])
