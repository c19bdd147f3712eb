;;; emacs_e2e.el --- headless Emacs + eglot against tvl-lsp on the test workspace (scout)  -*- lexical-binding: t; -*-
;; emacs --batch -l tests/editors/emacs_e2e.el ; env: TVL_LSP_REPO, TVL_LSP_CMD, TVL_E2E_WS, TVL_E2E_OUT
;; Emacs idle timers never fire in --batch, so the harness sends eglot's pending didChange itself.
;; Writes a JSON result {checks: [{name, ok, detail}], ok} to TVL_E2E_OUT.

;;; EXPECTATIONS (tune here)
(defconst e2e-launch "src/scout/launch/generic.launch")
(defconst e2e-expected-diagnostics '(("undefined-arg" 61 "stereo_cam") ("undefined-arg" 61 "'webcam'"))) ; (code line substring)
(defconst e2e-hover '(8 "Simulation" "384 of 1152"))                     ; (line word substring)
(defconst e2e-remove-arg "Map")                                        ; delete its <arg>, apply the fix
(defconst e2e-inserted-line "  <arg name=\"Map\"/>")
(defconst e2e-timeout 60)

(require 'json)
(defvar e2e-checks nil)
(defun e2e-check (name ok &optional detail)
  (push `((name . ,name) (ok . ,(if ok t :json-false)) (detail . ,(format "%s" detail))) e2e-checks)
  (message "%s %s %s" (if ok "PASS" "FAIL") name (or detail ""))
  ok)

(defun e2e-wait (pred &optional timeout)
  (let ((deadline (+ (float-time) (or timeout e2e-timeout))) v)
    (while (and (not (setq v (funcall pred))) (< (float-time) deadline))
      (accept-process-output nil 0.1))
    v))

(defun e2e-finish ()
  (let ((ok (and e2e-checks (seq-every-p (lambda (c) (eq (alist-get 'ok c) t)) e2e-checks))))
    (with-temp-file (getenv "TVL_E2E_OUT")
      (insert (json-encode `((ok . ,(if ok t :json-false)) (checks . ,(vconcat (reverse e2e-checks)))))))
    (ignore-errors (eglot-shutdown (eglot-current-server)))
    (kill-emacs (if ok 0 1))))

(defun e2e-steps ()
    (let* ((repo (getenv "TVL_LSP_REPO")) (ws (file-name-as-directory (getenv "TVL_E2E_WS"))))
      (add-to-list 'load-path (expand-file-name "editors/emacs" repo))
      (require 'tvl-lsp)
      (setq tvl-lsp-command (let ((c (getenv "TVL_LSP_CMD"))) ; a JSON list, or words
                                (if (string-prefix-p "[" c) (append (json-read-from-string c) nil) (split-string c))))
      (setq eglot-sync-connect t eglot-autoshutdown t)
      (find-file (expand-file-name e2e-launch ws))
      (e2e-check "launch file in roslaunch-mode" (eq major-mode 'roslaunch-mode) major-mode)
      (call-interactively #'eglot)
      (let ((server (e2e-wait #'eglot-current-server)))
        (e2e-check "eglot connected" server)
        (e2e-check "project root is the workspace"
                   (equal (file-name-as-directory (expand-file-name (project-root (eglot--project server))))
                          (expand-file-name ws))
                   (project-root (eglot--project server)))
        ;; diagnostics (flymake)
        (let* ((found (lambda ()
                        (seq-every-p
                         (lambda (e)
                           (seq-find (lambda (d)
                                       (and (= (line-number-at-pos (flymake-diagnostic-beg d)) (nth 1 e))
                                            (string-match-p (regexp-quote (nth 2 e)) (flymake-diagnostic-text d))))
                                     (flymake-diagnostics)))
                         e2e-expected-diagnostics)))
               (ok (e2e-wait found)))
          (e2e-check "expected diagnostics (flymake)" ok
                     (mapcar (lambda (d) (list (line-number-at-pos (flymake-diagnostic-beg d))
                                               (flymake-diagnostic-text d)))
                             (flymake-diagnostics)))
          (e2e-check "no other diagnostics" (= (length (flymake-diagnostics)) (length e2e-expected-diagnostics))))
        ;; hover, repeated while the server is still counting
        (goto-char (point-min)) (forward-line (1- (nth 0 e2e-hover)))
        (search-forward (nth 1 e2e-hover)) (backward-char 1)
        (let* ((text nil)
               (ok (e2e-wait (lambda ()
                               (let* ((r (jsonrpc-request server :textDocument/hover
                                                          (eglot--TextDocumentPositionParams)))
                                      (c (plist-get r :contents)))
                                 (setq text (if (stringp c) c (plist-get c :value)))
                                 (and text (string-match-p (regexp-quote (nth 2 e2e-hover)) text)))))))
          (e2e-check "hover shows the product count" ok text))
        ;; the add-missing-arg quick fix
        (goto-char (point-min))
        (search-forward (format "<arg name=\"%s\"" e2e-remove-arg))
        (delete-region (line-beginning-position) (1+ (line-end-position)))
        (eglot--signal-textDocument/didChange) ; what eglot does after eglot-send-changes-idle-time
        (let* ((missing (lambda ()
                          (seq-find (lambda (d) (string-match-p (format "`%s`" e2e-remove-arg)
                                                                (flymake-diagnostic-text d)))
                                    (flymake-diagnostics))))
               (diag (e2e-wait missing)))
          (e2e-check "missing-arg reported after the deletion" diag
                     (mapcar #'flymake-diagnostic-text (flymake-diagnostics)))
          (when diag
            (let* ((actions (jsonrpc-request
                             server :textDocument/codeAction
                             (list :textDocument (eglot--TextDocumentIdentifier)
                                   :range (list :start (eglot--pos-to-lsp-position (flymake-diagnostic-beg diag))
                                                :end (eglot--pos-to-lsp-position (flymake-diagnostic-end diag)))
                                   :context (list :diagnostics
                                                  (vector (alist-get 'eglot-lsp-diag (eglot--diag-data diag)))))))
                   (action (seq-find (lambda (a) (string-match-p e2e-remove-arg (plist-get a :title))) actions)))
              (e2e-check "a quick fix adds the arg" action (mapcar (lambda (a) (plist-get a :title)) actions))
              (when action
                (eglot--apply-workspace-edit (plist-get action :edit))
                (eglot--signal-textDocument/didChange) ; idle timers never fire in --batch
                (e2e-check "the arg line is back" (save-excursion (goto-char (point-min))
                                                                  (search-forward (concat "\n" e2e-inserted-line "\n") nil t)))
                (e2e-check "missing-arg gone after the fix" (e2e-wait (lambda () (not (funcall missing))))))))))))

(defun e2e-main ()
  (condition-case caught
      (e2e-steps)
    (error (e2e-check "harness ran without error" nil (format "%S" caught))))
  (e2e-finish))

(e2e-main)
