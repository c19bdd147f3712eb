;;; tvl-lsp.el --- TVL models and ROS launch files with the tvl-lsp server (eglot)  -*- lexical-binding: t; -*-

;; Usage (init.el), Emacs 28 with eglot (Debian: elpa-eglot) or Emacs 29+:
;;   (add-to-list 'load-path "/path/to/tvl-lsp/editors/emacs")
;;   (require 'tvl-lsp)
;;   (setq tvl-lsp-command '("/path/to/tvl-lsp/.venv/bin/tvl-lsp"))  ; if not on PATH
;;   (add-hook 'tvl-mode-hook #'eglot-ensure)
;;   (add-hook 'roslaunch-mode-hook #'eglot-ensure)
;;   (add-hook 'ros2-launch-python-mode-hook #'eglot-ensure)   ; *.launch.py, *_launch.py
;;
;; ROS 2 Python launch files (*.launch.py, *_launch.py) open in `ros2-launch-python-mode', a
;; `python-mode' (its highlighting, indentation and commands) whose eglot server is tvl-lsp;
;; every other Python file stays in `python-mode' with its own server.

;;; Code:

(require 'eglot)
(require 'nxml-mode)
(require 'project)
(require 'python)

(defgroup tvl-lsp nil "TVL feature models and ROS launch files." :group 'languages)

(defcustom tvl-lsp-command '("tvl-lsp")
  "Command that starts the tvl-lsp language server (LSP on stdio)."
  :type '(repeat string))

(defvar tvl-mode-syntax-table
  (let ((st (make-syntax-table)))
    (modify-syntax-entry ?/ ". 124b" st)
    (modify-syntax-entry ?* ". 23" st)
    (modify-syntax-entry ?\n "> b" st)
    (modify-syntax-entry ?_ "_" st)
    (modify-syntax-entry ?\" "\"" st)
    st))

(defconst tvl-font-lock-keywords
  `((,(regexp-opt '("root" "group" "include") 'words) . font-lock-keyword-face)
    (,(regexp-opt '("allOf" "oneOf" "someOf" "allof" "oneof" "someof") 'words) . font-lock-keyword-face)
    ("\\<\\(?:ifIn\\|ifOut\\|ifin\\|ifout\\)\\s-*:" . font-lock-keyword-face)
    (,(regexp-opt '("opt" "shared" "const" "constant") 'words) . font-lock-builtin-face)
    (,(regexp-opt '("int" "real" "bool" "enum" "struct") 'words) . font-lock-type-face)
    (,(regexp-opt '("true" "false") 'words) . font-lock-constant-face)
    (,(regexp-opt '("this" "parent" "children" "selectedChildren" "selectedchildren") 'words) . font-lock-variable-name-face)
    ("\\<root\\s-+\\([A-Za-z_][A-Za-z0-9_]*\\)" 1 font-lock-type-face)
    ("^\\s-*\\([A-Za-z_][A-Za-z0-9_]*\\)\\s-*{" 1 font-lock-type-face)))

;;;###autoload
(define-derived-mode tvl-mode prog-mode "TVL"
  "Major mode for TVL feature models."
  (setq-local comment-start "// ")
  (setq-local comment-end "")
  (setq-local font-lock-defaults '(tvl-font-lock-keywords)))

;;;###autoload
(define-derived-mode roslaunch-mode nxml-mode "roslaunch"
  "Major mode for ROS 1 launch files (XML).")

;;;###autoload
(define-derived-mode ros2-launch-python-mode python-mode "ROS2-launch.py"
  "Major mode for ROS 2 launch files written in Python (`python-mode', served by tvl-lsp).")

;;;###autoload
(progn
  (add-to-list 'auto-mode-alist '("\\(?:\\.\\|_\\)launch\\.py\\'" . ros2-launch-python-mode))
  (add-to-list 'auto-mode-alist '("\\.tvl\\'" . tvl-mode))
  (add-to-list 'auto-mode-alist '("\\.launch\\(?:\\.xml\\)?\\'" . roslaunch-mode))
  (add-to-list 'auto-mode-alist '("_launch\\.xml\\'" . roslaunch-mode))
  (add-to-list 'auto-mode-alist '("\\.test\\'" . roslaunch-mode)))

(defun tvl-lsp--colcon-root-p (d)
  "Is D a colcon (ROS 2) workspace: no package itself, with a src folder?"
  (and (file-directory-p (expand-file-name "src" d))
       (not (file-exists-p (expand-file-name "package.xml" d)))))

(defun tvl-lsp-project-find (dir)
  "The workspace above DIR: the folder with .catkin_workspace, .catkin_tools or haros*.yaml;
else (outside a git repository, which project.el finds) the colcon workspace: the parent of
the src folder that holds the packages."
  (let ((root (or (locate-dominating-file
                   dir (lambda (d)
                         (and (file-directory-p d)
                              (or (file-exists-p (expand-file-name ".catkin_workspace" d))
                                  (file-exists-p (expand-file-name ".catkin_tools" d))
                                  (directory-files d nil "\\`haros.*\\.ya?ml\\'" t)))))
                  (and (not (locate-dominating-file dir ".git"))
                       (locate-dominating-file dir #'tvl-lsp--colcon-root-p)))))
    (when (and root (memq major-mode '(tvl-mode roslaunch-mode ros2-launch-python-mode)))
      (cons 'transient (expand-file-name root)))))

(add-hook 'project-find-functions #'tvl-lsp-project-find -50)

(add-to-list 'eglot-server-programs
             `((tvl-mode roslaunch-mode ros2-launch-python-mode) . ,(lambda (&rest _) tvl-lsp-command)))

(provide 'tvl-lsp)
;;; tvl-lsp.el ends here
