"""The command line: one module per command (``cli/<name>.py``, one ``<name>_command``, one line
in ``_COMMANDS`` of :mod:`.app`), the options they share (:mod:`.options`), the renderings of
``validate``'s report (:mod:`.reports`) and the JSON Schemas of every report (:mod:`.schemas`).

May import every layer (``motionfmt``, ``kinematics``, ``sim``) and the top-level modules (errors,
extras, stamps, disk_cache, exit_codes); nothing imports ``cli``.
"""
