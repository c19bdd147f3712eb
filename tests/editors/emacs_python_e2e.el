;;; emacs_python_e2e.el --- headless Emacs + eglot against tvl-lsp on a ROS 2 Python launch file  -*- lexical-binding: t; -*-
;; emacs --batch -l tests/editors/emacs_python_e2e.el ; env: TVL_LSP_REPO, TVL_LSP_CMD, TVL_E2E_WS, TVL_E2E_OUT
;; On a copy of tests/data/ros2py_editor/ws: rover.launch.py opens in ros2-launch-python-mode (a
;; python-mode), eglot connects to tvl-lsp at the workspace, the four planted problems arrive
;; (flymake), a hover gives a feature's product count; an ordinary Python module stays in
;; python-mode without tvl-lsp.  Writes {checks: [{name, ok, detail}], ok} to TVL_E2E_OUT.

(defconst e2e-launch "src/rover/launch/rover.launch.py")
(defconst e2e-plain "src/rover/rover/util.py")
(defconst e2e-expected '("Sonar" "Teleop" "planner" "sensor"))  ; one substring per planted problem
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
    (setq tvl-lsp-command (let ((c (getenv "TVL_LSP_CMD")))
                            (if (string-prefix-p "[" c) (append (json-read-from-string c) nil) (split-string c))))
    (setq eglot-sync-connect t eglot-autoshutdown t)
    (find-file (expand-file-name e2e-launch ws))
    (e2e-check "launch file in ros2-launch-python-mode, a python-mode"
               (and (eq major-mode 'ros2-launch-python-mode) (derived-mode-p 'python-mode)) major-mode)
    (call-interactively #'eglot)
    (let ((server (e2e-wait #'eglot-current-server)))
      (e2e-check "eglot connected" server)
      (e2e-check "project root is the workspace"
                 (equal (file-name-as-directory (expand-file-name (project-root (eglot--project server))))
                        (expand-file-name ws))
                 (project-root (eglot--project server)))
      (let ((ok (e2e-wait (lambda ()
                            (seq-every-p (lambda (s) (seq-find (lambda (d) (string-match-p (regexp-quote s)
                                                                                           (flymake-diagnostic-text d)))
                                                               (flymake-diagnostics)))
                                         e2e-expected)))))
        (e2e-check "the four planted problems (flymake)" (and ok (= (length (flymake-diagnostics)) 4))
                   (mapcar #'flymake-diagnostic-text (flymake-diagnostics))))
      (goto-char (point-min))
      (search-forward "DeclareLaunchArgument('Camera'")
      (backward-char 3)
      (let* ((text nil)
             (ok (e2e-wait (lambda ()
                             (let* ((r (jsonrpc-request server :textDocument/hover (eglot--TextDocumentPositionParams)))
                                    (c (plist-get r :contents)))
                               (setq text (if (stringp c) c (plist-get c :value)))
                               (and text (string-match-p "12 of 24 products" text)))))))
        (e2e-check "hover shows the product count" ok text)))
    (find-file (expand-file-name e2e-plain ws))
    (e2e-check "ordinary Python stays in python-mode" (eq major-mode 'python-mode) major-mode)
    (e2e-check "and has no tvl-lsp server" (null (eglot-current-server)))))

(condition-case caught
    (e2e-steps)
  (error (e2e-check "harness ran without error" nil (format "%S" caught))))
(e2e-finish)
