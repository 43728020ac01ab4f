# The tools' command-line contracts, through jetrace_cli_test (CMakeLists.txt):
# a bad argument exits non-zero (EXPECT_FAIL) with a message (REGEX, where
# another failure would also exit non-zero), and a tool prints what it
# promises.

# jetrace-sim and jetrace-bench.
jetrace_cli_test(NAME cli_sim_rejects_zero_cars COMMAND jetrace-sim --cars 0 EXPECT_FAIL LABELS quick)
jetrace_cli_test(NAME cli_sim_rejects_unknown_track COMMAND jetrace-sim --track nosuch EXPECT_FAIL LABELS quick)
jetrace_cli_test(NAME cli_sim_rejects_missing_obj COMMAND jetrace-sim --track /nonexistent/track.obj EXPECT_FAIL LABELS quick)
jetrace_cli_test(NAME cli_bench_rejects_no_subcommand COMMAND jetrace-bench EXPECT_FAIL LABELS quick)
jetrace_cli_test(NAME cli_bench_rejects_zero_frames COMMAND jetrace-bench seed --frames 0 EXPECT_FAIL LABELS quick)
jetrace_cli_test(NAME cli_sim_prints_state_hash COMMAND jetrace-sim --track ring --cars 2 --seconds 2 --seed 3 LABELS quick
  REGEX "state_hash=[0-9a-f][0-9a-f][0-9a-f][0-9a-f][0-9a-f][0-9a-f][0-9a-f][0-9a-f][0-9a-f][0-9a-f][0-9a-f][0-9a-f][0-9a-f][0-9a-f][0-9a-f][0-9a-f]\n")
# The seed's benchmark, and an exact check of the grid: a parked car and one
# pushed out every frame, grid on and off, all end in the same state (the
# command exits 1 if not: REGEX ignores the exit code, so it is printed).
jetrace_cli_test(NAME cli_bench_seed_prints_json
  COMMAND sh -c "\"$0\" seed --frames 1000 --repeats 1; echo exit=$?" $<TARGET_FILE:jetrace-bench> LABELS quick
  REGEX "\"parked_grid_off_ns_per_frame\":[0-9.e+-]+.*\"parked_grid_on_ns_per_frame\":[0-9.e+-]+.*\"pushout_grid_off_ns_per_frame\":[0-9.e+-]+.*\"pushout_grid_on_ns_per_frame\":[0-9.e+-]+.*\"same_final_state\":true.*exit=0")

# The track benchmarks on small meshes: their JSON and the same identity
# through OBJ and .jtrack (a few seconds).
jetrace_cli_test(NAME cli_bench_track_load_prints_json COMMAND jetrace-bench track-load --squares 32 --repeats 1
  REGEX "\"identity_equal\":true" LABELS quick TIMEOUT 60)
jetrace_cli_test(NAME cli_bench_density_prints_json COMMAND jetrace-bench density --squares 16 32 --seconds 1 --repeats 1
  REGEX "\"ns_per_car_step\":[0-9.e+-]+,.*\"triangles\":512.*\"triangles\":2048" LABELS quick TIMEOUT 60)
# jetrace-bench server: a RaceServer and AI bots over the in-memory network.
# Its JSON, and the same bytes and state hash in every run: --repeats 2
# checks two runs in one process (exit 1 if they differ), a second process
# must print the same again.
jetrace_cli_test(NAME cli_bench_server_prints_json_and_repeats
  COMMAND sh -c "args='server --track ring --bots 4 --seconds 2' && a=\$(\"$0\" \$args --repeats 2) && b=\$(\"$0\" \$args) && echo \"\$a\" && f() { echo \"\$1\" | grep -o '\"bytes_[a-z_]*\":[0-9.e+-]*\\|\"state_hash\":\"[0-9a-f]*\"'; } && test \"\$(f \"\$a\")\" = \"\$(f \"\$b\")\" && echo same-bytes-and-hash; echo exit=\$?" $<TARGET_FILE:jetrace-bench>
  REGEX "\"benchmark\":\"server\",\"bots\":4,\"bytes_down\":[1-9][0-9]*,\"bytes_down_per_client_per_s\":[0-9.e+]+,\"bytes_up\":[1-9][0-9]*,\"bytes_up_per_client_per_s\":[0-9.e+]+,.*\"state_hash\":\"[0-9a-f][0-9a-f][0-9a-f][0-9a-f][0-9a-f][0-9a-f][0-9a-f][0-9a-f][0-9a-f][0-9a-f][0-9a-f][0-9a-f][0-9a-f][0-9a-f][0-9a-f][0-9a-f]\".*\"tick_us_median\":[0-9.e+-]+,.*\"tick_us_p99\":[0-9.e+-]+,.*\"ticks\":240,\"track\":\"ring\".*same-bytes-and-hash\nexit=0"
  LABELS quick TIMEOUT 120)
jetrace_cli_test(NAME cli_bench_server_rejects_zero_bots COMMAND jetrace-bench server --bots 0 EXPECT_FAIL LABELS quick)
jetrace_cli_test(NAME cli_bench_server_rejects_65_bots COMMAND jetrace-bench server --bots 65 EXPECT_FAIL LABELS quick)
jetrace_cli_test(NAME cli_bench_server_rejects_unknown_track COMMAND jetrace-bench server --track nosuch EXPECT_FAIL LABELS quick)
jetrace_cli_test(NAME cli_bench_server_rejects_zero_repeats COMMAND jetrace-bench server --repeats 0 EXPECT_FAIL LABELS quick)
jetrace_cli_test(NAME cli_bench_server_rejects_negative_latency COMMAND jetrace-bench server --latency-ms -1
  EXPECT_FAIL LABELS quick)
jetrace_cli_test(NAME cli_bench_server_rejects_nan_seconds
  COMMAND sh -c "\"$0\" server --seconds nan 2>&1; echo exit=$?" $<TARGET_FILE:jetrace-bench>
  REGEX "--seconds: Value nan is not a finite number.*exit=[1-9]" LABELS quick)
# jetrace-bench landscape writes the landscape as an OBJ track that races
# (tools/view_bench.sh's input); bad sizes and an unwritable file fail.
jetrace_cli_test(NAME cli_bench_landscape_writes_obj
  COMMAND sh -c "out=\$(mktemp -d) && \"$0\" landscape --squares 20 --spawns 64 --out \$out/l.obj && \"$1\" --track \$out/l.obj --cars 64 --seconds 1; s=\$?; rm -rf \$out; exit \$s"
          $<TARGET_FILE:jetrace-bench> $<TARGET_FILE:jetrace-sim>
  REGEX "\"gates\":16,.*\"spawns\":64,\"track\":\"landscape-20\",\"triangles\":800}.*64 cars.*state_hash=" LABELS quick TIMEOUT 60)
jetrace_cli_test(NAME cli_bench_landscape_rejects_one_square COMMAND jetrace-bench landscape --squares 1 --out x.obj
  EXPECT_FAIL LABELS quick)
jetrace_cli_test(NAME cli_bench_landscape_rejects_65_spawns COMMAND jetrace-bench landscape --spawns 65 --out x.obj
  EXPECT_FAIL LABELS quick)
jetrace_cli_test(NAME cli_bench_landscape_rejects_unwritable
  COMMAND sh -c "\"$0\" landscape --squares 2 --out /proc/jetrace-no-such-dir/l.obj 2>&1; echo exit=$?" $<TARGET_FILE:jetrace-bench>
  REGEX "cannot write /proc/jetrace-no-such-dir/l.obj.*exit=1" LABELS quick)
# tools/view_bench.sh refuses bad arguments before it starts anything.
jetrace_cli_test(NAME cli_view_bench_rejects_bad_seconds
  COMMAND sh -c "\"$0\" --seconds nan 2>&1; echo exit=$?" ${PROJECT_SOURCE_DIR}/tools/view_bench.sh
  REGEX "--seconds must be a whole number.*exit=2" LABELS quick)

# The real levels (docs/tracks/godot-*, sauerbraten-*, redeclipse-*, through docs/tracks/*.track.json): 8 AI
# cars race a few seconds on each (laps are not asserted). Then jetrace-track.
foreach(level truck_town zdm2 fdm6 pandora dutility)
  jetrace_cli_test(NAME sim_real_track_${level}
    COMMAND jetrace-sim --track ${PROJECT_SOURCE_DIR}/docs/tracks/${level}.track.json --cars 8 --seconds 5
    REGEX "state_hash=[0-9a-f]+" LABELS quick TIMEOUT 120)
endforeach()
jetrace_cli_test(NAME cli_track_inspect_json COMMAND jetrace-track inspect ${PROJECT_SOURCE_DIR}/docs/tracks/zdm2.track.json --json
  REGEX "\"degenerate_dropped\":1134.*\"gates\":10.*\"raceable\":true.*\"triangles\":57638" LABELS quick TIMEOUT 60)
# A drivability warning (docs/TRACKS.md, "Drivability warnings"): a gate hanging above the road.
jetrace_cli_test(NAME cli_track_inspect_warns_gate_above_road
  COMMAND jetrace-track inspect ${PROJECT_SOURCE_DIR}/tests/tracks/data/gate_above_road.obj --json
  REGEX "\"drivability\":\\[{\"index\":1,\"kind\":\"gate_above_road\",\"message\":\"gate 1 at \\(20.0, 14.0, 0.0\\): its bottom edge is 10.0 m above the road[^}]*\"subject\":\"gate\"}\\]" LABELS quick TIMEOUT 20)
jetrace_cli_test(NAME cli_track_render_svg COMMAND sh -c "out=\$(mktemp -d) && \"$0\" render ring --svg \$out/r.svg && grep -q '<svg' \$out/r.svg && grep -q '>11</text>' \$out/r.svg; s=\$?; rm -rf \$out; exit \$s" $<TARGET_FILE:jetrace-track>
  LABELS quick TIMEOUT 60)
jetrace_cli_test(NAME cli_track_requires_subcommand COMMAND jetrace-track EXPECT_FAIL LABELS quick TIMEOUT 20)
jetrace_cli_test(NAME cli_track_render_requires_svg COMMAND jetrace-track render ring EXPECT_FAIL LABELS quick TIMEOUT 20)
# Matched on the message and a non-zero exit: name|arguments|message.
foreach(spec
    "cli_track_rejects_missing_file|inspect /nonexistent/t.track.json|cannot open '/nonexistent/t.track.json'"
    "cli_track_rejects_unknown_track|inspect nosuch|unknown track 'nosuch'"
    "cli_track_rejects_bad_width|render ring --svg /tmp/x.svg --width 5|--width: Value 5 not in range"
    "cli_track_reports_failed_write|render ring --svg /proc/jetrace-no-such/x.svg|cannot write '/proc/jetrace-no-such/x.svg'")
  string(REPLACE "|" ";" parts "${spec}")
  list(GET parts 0 name)
  list(GET parts 1 args)
  list(GET parts 2 message)
  separate_arguments(args)
  jetrace_cli_test(NAME ${name} COMMAND sh -c "\"$0\" \"$@\" 2>&1; echo exit=$?" $<TARGET_FILE:jetrace-track> ${args}
    REGEX "${message}.*exit=[1-9]" LABELS quick TIMEOUT 20)
endforeach()

# jetrace-server's options. Matched on the message: an older server without
# the option also exits non-zero. name|arguments...|message.
foreach(spec
    "nan_drain_timeout|--drain-timeout;nan|--drain-timeout: Value nan is not a finite number"
    "infinite_lobby_timeout|--lobby-timeout;inf|--lobby-timeout: Value inf is not a finite number"
    "negative_lobby_timeout|--lobby-timeout;-1|--lobby-timeout: Value -1 not in range"
    "nan_countdown|--countdown;nan|--countdown: Value nan is not a finite number"
    "nan_health_period|--agones-health-period;nan|--agones-health-period: Value nan is not a finite number"
    "zero_finish_window|--finish-window;0|--finish-window: Value 0 not in range \\(0, 3600\\]"
    "long_hello_timeout|--hello-timeout;1e6|--hello-timeout: Value 1e6 not in range \\[0.001, 86400\\]"
    "scaled_hello_timeout|--hello-timeout;1000;--time-scale;100|--hello-timeout 1000 times --time-scale 100 is 100000 s"
    "huge_finish_window|--finish-window;1e400|--finish-window: Value 1e400 is out of the range of a double"
    "unknown_lobby_action|--lobby-timeout;5;--lobby-timeout-action;wait|--lobby-timeout-action: wait not in"
    "cancel_without_lobby_timeout|--lobby-timeout-action;cancel|--lobby-timeout-action cancel needs --lobby-timeout"
    "nonce_file_without_key|--nonce-file;/tmp/jetrace-nonces|--nonce-file needs --key-file"
    "bad_pre_hello_limit|--pre-hello-limit;5000|--pre-hello-limit: Value 5000 not in range"
    "nan_linger|--linger;nan|--linger: Value nan is not a finite number"
    "nan_input_hold|--input-hold;nan|--input-hold: Value nan is not a finite number"
    "long_input_hold|--input-hold;61|--input-hold: Value 61 not in range \\[0, 60\\]"
    "negative_linger|--linger;-1|--linger: Value -1 not in range \\[0, 3600\\]"
    "scaled_linger|--linger;100;--time-scale;100|--linger 100 times --time-scale 100 is 10000 s"
    "bad_web|--web;nowhere|--web: 'nowhere' is not PORT or ADDR:PORT"
    "web_origin_without_web|--web-origin;http://x|--web-origin, --web-cert, --web-key, --web-link and the --webrtc flags need --web"
    "webrtc_port_without_web|--webrtc-port;5000|--web-origin, --web-cert, --web-key, --web-link and the --webrtc flags need --web"
    "web_link_without_web|--web-link;latency=5|--web-origin, --web-cert, --web-key, --web-link and the --webrtc flags need --web"
    "bad_web_link_name|--web;0;--web-link;speed=5|--web-link: unknown condition 'speed'"
    "nan_web_link|--web;0;--web-link;loss=nan|--web-link: loss must be a number in \\[0, 1\\]"
    "bad_web_link_item|--web;0;--web-link;latency|--web-link: 'latency' is not NAME=VALUE"
    "bad_webrtc_address|--web;0;--webrtc-address;nowhere|--webrtc-address nowhere: not an IP address"
    "bad_webrtc_port|--web;0;--webrtc-port;70000|--webrtc-port: Value 70000 not in range"
    "bad_web_origin|--web;0;--web-origin;x.example|--web-origin x.example: an origin is http://HOST"
    "web_cert_without_key|--web;0;--web-cert;${CMAKE_CURRENT_SOURCE_DIR}/CMakeLists.txt|--web-cert and --web-key go together"
    "web_cert_not_pem|--web;0;--web-cert;${CMAKE_CURRENT_SOURCE_DIR}/CMakeLists.txt;--web-key;${CMAKE_CURRENT_SOURCE_DIR}/CMakeLists.txt|--web-cert .*CMakeLists.txt: "
    "missing_web_key|--web;0;--web-key;/nonexistent/key.pem|--web-key: File does not exist"
    "zero_web_sockets|--web;0;--web-max-sockets;0|--web-max-sockets: Value 0 not in range")
  string(REPLACE "|" ";" parts "${spec}")
  list(GET parts 0 name)
  list(GET parts -1 message)
  list(REMOVE_AT parts 0 -1)
  jetrace_cli_test(NAME cli_server_rejects_${name} COMMAND jetrace-server ${parts} --port 0
    REGEX "${message}" LABELS quick TIMEOUT 20)
endforeach()
jetrace_cli_test(NAME cli_server_names_default_snapshot_rate COMMAND jetrace-server --tick-rate 100 --snapshot-rate 7 --port 0
  REGEX "the default snapshot rate is 50 Hz" LABELS quick TIMEOUT 20)
jetrace_cli_test(NAME cli_server_rejects_sign_key_without_record
  COMMAND jetrace-server --port 0 --sign-key ${CMAKE_CURRENT_SOURCE_DIR}/CMakeLists.txt
  REGEX "--sign-key needs --record" LABELS quick TIMEOUT 20)
jetrace_cli_test(NAME cli_server_rejects_bad_snapshot_rate COMMAND jetrace-server --snapshot-rate 7 --port 0
  EXPECT_FAIL LABELS quick TIMEOUT 20)
jetrace_cli_test(NAME cli_server_rejects_unknown_track COMMAND jetrace-server --track nosuch --port 0
  EXPECT_FAIL LABELS quick TIMEOUT 20)
jetrace_cli_test(NAME cli_server_rejects_negative_reconnect_grace COMMAND jetrace-server --reconnect-grace -1 --port 0
  EXPECT_FAIL LABELS quick TIMEOUT 20)
jetrace_cli_test(NAME cli_server_rejects_race_id_without_key COMMAND jetrace-server --race-id cup --port 0
  EXPECT_FAIL LABELS quick TIMEOUT 20)
jetrace_cli_test(NAME cli_server_rejects_zero_hello_timeout COMMAND jetrace-server --hello-timeout 0 --port 0
  EXPECT_FAIL LABELS quick TIMEOUT 20)
# Matched on the message and the exit code (2, before listening).
jetrace_cli_test(NAME cli_server_rejects_results_in_missing_dir
  COMMAND sh -c "\"$0\" --results /nonexistent/r-%n.json --port 0 2>&1; echo exit=$?" $<TARGET_FILE:jetrace-server>
  REGEX "cannot create files in the directory '/nonexistent' of '/nonexistent/r-1.json': No such file or directory\nexit=2"
  LABELS quick TIMEOUT 20)
jetrace_cli_test(NAME cli_server_rejects_record_in_missing_dir
  COMMAND sh -c "\"$0\" --record /nonexistent/race.replay --port 0 2>&1; echo exit=$?" $<TARGET_FILE:jetrace-server>
  REGEX "'/nonexistent/race.replay': No such file or directory\nexit=2" LABELS quick TIMEOUT 20)
jetrace_cli_test(NAME cli_server_rejects_missing_key_file
  COMMAND sh -c "\"$0\" --key-file /nonexistent --port 0 2>&1; echo exit=$?" $<TARGET_FILE:jetrace-server>
  REGEX "key file '/nonexistent': No such file or directory.*exit=2" LABELS quick TIMEOUT 20)

# jetrace-bot's options.
jetrace_cli_test(NAME cli_bot_rejects_nan_max_seconds COMMAND jetrace-bot --connect 127.0.0.1:9 --max-seconds nan
  REGEX "--max-seconds: Value nan is not a finite number" LABELS quick TIMEOUT 20)
jetrace_cli_test(NAME cli_bot_rejects_infinite_time_scale COMMAND jetrace-bot --connect 127.0.0.1:9 --time-scale inf
  REGEX "--time-scale: Value inf is not a finite number" LABELS quick TIMEOUT 20)
# Matched on CLI11's message: a bot that ran instead would also exit non-zero.
jetrace_cli_test(NAME cli_bot_rejects_negative_join_window COMMAND jetrace-bot --connect 127.0.0.1:9 --join-window -1
  REGEX "--join-window: Value -1 not in range" LABELS quick TIMEOUT 20)
jetrace_cli_test(NAME cli_bot_rejects_zero_join_limit COMMAND jetrace-bot --connect 127.0.0.1:9 --join-limit 0
  REGEX "--join-limit: Value 0 not in range" LABELS quick TIMEOUT 20)
jetrace_cli_test(NAME cli_bot_rejects_input_delay_over_30_ticks COMMAND jetrace-bot --connect 127.0.0.1:9 --input-delay 31
  REGEX "--input-delay: Value 31 not in range" LABELS quick TIMEOUT 20)
jetrace_cli_test(NAME cli_bot_rejects_fractional_input_delay COMMAND jetrace-bot --connect 127.0.0.1:9 --input-delay 2.5
  REGEX "--input-delay: Value 2.5 not in range" LABELS quick TIMEOUT 20)
jetrace_cli_test(NAME cli_bot_rejects_nan_input_delay COMMAND jetrace-bot --connect 127.0.0.1:9 --input-delay nan
  REGEX "--input-delay: Value nan not in range" LABELS quick TIMEOUT 20)
jetrace_cli_test(NAME cli_bot_rejects_invalid_utf8_name
  COMMAND sh -c "\"$0\" --connect 127.0.0.1:9 --name \"$(printf 'a\\377')\" 2>&1; echo exit=$?" $<TARGET_FILE:jetrace-bot>
  REGEX "--name must be valid UTF-8 text of at most 30 bytes\nexit=2" LABELS quick TIMEOUT 20)
jetrace_cli_test(NAME cli_bot_rejects_bad_address COMMAND jetrace-bot --connect nohostport EXPECT_FAIL LABELS quick TIMEOUT 20)
jetrace_cli_test(NAME cli_bot_requires_connect COMMAND jetrace-bot --count 2 EXPECT_FAIL LABELS quick TIMEOUT 20)
jetrace_cli_test(NAME cli_bot_rejects_malformed_token COMMAND jetrace-bot --connect 127.0.0.1:9 --track ring --token AAAA
  EXPECT_FAIL LABELS quick TIMEOUT 20)

# jetrace-sim's and jetrace-verify's replay options. Matched on the message
# where the wrong refusal would also exit non-zero.
jetrace_cli_test(NAME cli_sim_rejects_garbage_replay COMMAND jetrace-sim --replay ${CMAKE_CURRENT_SOURCE_DIR}/CMakeLists.txt
  EXPECT_FAIL LABELS quick TIMEOUT 20)
jetrace_cli_test(NAME cli_sim_rejects_directory_replay COMMAND jetrace-sim --verify ${CMAKE_CURRENT_SOURCE_DIR}
  REGEX "is a directory" LABELS quick TIMEOUT 20)
jetrace_cli_test(NAME cli_sim_rejects_device_replay COMMAND jetrace-sim --verify /dev/zero
  REGEX "is not a regular file" LABELS quick TIMEOUT 20)
jetrace_cli_test(NAME cli_sim_rejects_nan_seconds COMMAND jetrace-sim --seconds nan
  REGEX "not a finite number" LABELS quick TIMEOUT 20)
jetrace_cli_test(NAME cli_sim_rejects_bad_expect COMMAND jetrace-sim --verify ${CMAKE_CURRENT_SOURCE_DIR}/CMakeLists.txt
  --expect 12345 REGEX "is not 16 hex digits" LABELS quick TIMEOUT 20)
jetrace_cli_test(NAME cli_sim_rejects_one_diff_without_rebuild COMMAND jetrace-sim --diff ${CMAKE_CURRENT_SOURCE_DIR}/CMakeLists.txt
  REGEX "--diff takes two replays" LABELS quick TIMEOUT 20)
jetrace_cli_test(NAME cli_sim_rejects_two_modes COMMAND jetrace-sim --verify a --synctest b
  REGEX "at most 1 options" LABELS quick TIMEOUT 20)
jetrace_cli_test(NAME cli_sim_rejects_zero_rollback COMMAND jetrace-sim --synctest a --rollback 0
  REGEX "--rollback: Value 0 not in range" LABELS quick TIMEOUT 20)
jetrace_cli_test(NAME cli_verify_rejects_bad_expect COMMAND jetrace-verify ${CMAKE_CURRENT_SOURCE_DIR}/CMakeLists.txt --expect zz
  REGEX "is not 16 hex digits" LABELS quick TIMEOUT 20)

# jetrace-token.
jetrace_cli_test(NAME cli_token_requires_subcommand COMMAND jetrace-token EXPECT_FAIL LABELS quick TIMEOUT 20)
jetrace_cli_test(NAME cli_token_issue_rejects_missing_key
  COMMAND jetrace-token issue --key-file /nonexistent --name a --valid-for 5 EXPECT_FAIL LABELS quick TIMEOUT 20)
jetrace_cli_test(NAME cli_token_issue_rejects_zero_validity
  COMMAND jetrace-token issue --key-file /nonexistent --name a --valid-for 0 EXPECT_FAIL LABELS quick TIMEOUT 20)
jetrace_cli_test(NAME cli_token_inspect_rejects_garbage COMMAND jetrace-token inspect "not a token!"
  EXPECT_FAIL LABELS quick TIMEOUT 20)

# jetrace-netsim.
jetrace_cli_test(NAME cli_netsim_requires_forward COMMAND jetrace-netsim --listen 0 EXPECT_FAIL LABELS quick TIMEOUT 20)
jetrace_cli_test(NAME cli_netsim_requires_listen COMMAND jetrace-netsim --forward 127.0.0.1:27910
  EXPECT_FAIL LABELS quick TIMEOUT 20)
jetrace_cli_test(NAME cli_netsim_rejects_bad_forward COMMAND jetrace-netsim --listen 0 --forward nohostport --duration 1
  EXPECT_FAIL LABELS quick TIMEOUT 20)
jetrace_cli_test(NAME cli_netsim_rejects_loss_above_one COMMAND jetrace-netsim --listen 0 --forward 127.0.0.1:9 --loss 1.5
  EXPECT_FAIL LABELS quick TIMEOUT 20)
jetrace_cli_test(NAME cli_netsim_rejects_negative_latency
  COMMAND jetrace-netsim --listen 0 --forward 127.0.0.1:9 --up-latency -5 EXPECT_FAIL LABELS quick TIMEOUT 20)
jetrace_cli_test(NAME cli_netsim_rejects_bad_port COMMAND jetrace-netsim --listen 70000 --forward 127.0.0.1:9
  EXPECT_FAIL LABELS quick TIMEOUT 20)
jetrace_cli_test(NAME cli_netsim_rejects_unbindable_address
  COMMAND jetrace-netsim --listen 0 --bind 192.0.2.1 --forward 127.0.0.1:9 --duration 1 EXPECT_FAIL LABELS quick TIMEOUT 20)
jetrace_cli_test(NAME cli_netsim_rejects_nan_loss COMMAND jetrace-netsim --listen 0 --forward 127.0.0.1:9 --loss nan
  REGEX "--loss: Value nan is not a finite number" LABELS quick TIMEOUT 20)
jetrace_cli_test(NAME cli_netsim_prints_counters COMMAND jetrace-netsim --listen 0 --forward 127.0.0.1:9 --duration 0.2
  REGEX "listening on 127.0.0.1:[0-9]+\n.*\"up\":{.*\"rate_limited\":0" LABELS quick TIMEOUT 20)

# jetrace-bench study: its quick mode writes every CSV file.
jetrace_cli_test(NAME bench_study_quick COMMAND ${CMAKE_COMMAND} -E env
  sh -c "out=\$(mktemp -d) && $<TARGET_FILE:jetrace-bench> study --quick --repeats 1 --out \$out && for f in integrators spring resolver tunnelling grid_cell track_size cars pareto; do test -s \$out/\$f.csv || { echo missing \$f.csv; exit 1; }; done; rm -rf \$out"
  LABELS quick TIMEOUT 120)
jetrace_cli_test(NAME cli_bench_study_rejects_zero_repeats COMMAND jetrace-bench study --repeats 0 EXPECT_FAIL LABELS quick)
jetrace_cli_test(NAME cli_bench_study_rejects_unwritable_out COMMAND jetrace-bench study --quick --out /proc/jetrace-no-such-dir
  EXPECT_FAIL LABELS quick)

# jetrace-bench bullet, side by side with Bullet: one JSON line per scenario with its keys.
if(JETRACE_HAVE_BULLET)
  set(_num "[0-9.e+-]+")
  jetrace_cli_test(NAME bench_bullet_prints_json COMMAND jetrace-bench bullet --quick --frames 50 --repeats 1
    LABELS quick TIMEOUT 120 REGEX
    "\"bullet_ns_per_step\":${_num}.*\"jetrace_ns_per_step\":${_num}.*\"scenario\":\"idle\".*\"bullet_ns_per_step\":${_num}.*\"jetrace_ns_per_step\":${_num}.*\"scenario\":\"driving\".*\"bullet_ccd_limit_mps\":${_num}.*\"bullet_limit_mps\":${_num}.*\"bullet_ns_per_step\":${_num}.*\"jetrace_limit_mps\":${_num}.*\"jetrace_ns_per_step\":${_num}.*\"scenario\":\"thin_wall\"")
  jetrace_cli_test(NAME cli_bench_bullet_rejects_zero_frames COMMAND jetrace-bench bullet --frames 0 EXPECT_FAIL LABELS quick)
  jetrace_cli_test(NAME cli_bench_bullet_rejects_unknown_scenario COMMAND jetrace-bench bullet --scenario nosuch
    EXPECT_FAIL LABELS quick)
  # One scenario, jetrace only: what the callgrind figure of docs/ACCURACY.md runs.
  jetrace_cli_test(NAME bench_bullet_jetrace_only_driving
    COMMAND jetrace-bench bullet --scenario driving --jetrace-only --frames 50 --repeats 1
    REGEX "\"jetrace_ns_per_step\":${_num}.*\"scenario\":\"driving\"" FAIL_REGEX "bullet_" LABELS quick TIMEOUT 60)
  # The thin wall, jetrace only: the step's cost without Bullet or the speed-limit search (tools/bench_compare.sh).
  jetrace_cli_test(NAME bench_bullet_jetrace_only_thin_wall
    COMMAND jetrace-bench bullet --scenario thin_wall --jetrace-only --quick --repeats 1
    REGEX "\"jetrace_ns_per_step\":${_num}.*\"scenario\":\"thin_wall\"" FAIL_REGEX "bullet_|limit_mps" LABELS quick TIMEOUT 60)
endif()

# jetrace-server's hosting options (label ops too).
jetrace_cli_test(NAME cli_server_rejects_bad_metrics_port COMMAND jetrace-server --metrics 127.0.0.1:70000 --port 0
  EXPECT_FAIL LABELS quick ops TIMEOUT 20)
jetrace_cli_test(NAME cli_server_rejects_metrics_without_port COMMAND jetrace-server --metrics 127.0.0.1: --port 0
  EXPECT_FAIL LABELS quick ops TIMEOUT 20)
jetrace_cli_test(NAME cli_server_rejects_zero_health_period
  COMMAND jetrace-server --agones --agones-health-period 0 --port 0 EXPECT_FAIL LABELS quick ops TIMEOUT 20)
jetrace_cli_test(NAME cli_server_rejects_zero_connect_timeout
  COMMAND jetrace-server --agones --agones-connect-timeout 0 --port 0 EXPECT_FAIL LABELS quick ops TIMEOUT 20)
jetrace_cli_test(NAME cli_server_rejects_bad_agones_port
  COMMAND sh -c "AGONES_SDK_HTTP_PORT=9x \"$0\" --port 0 2>&1; echo exit=$?" $<TARGET_FILE:jetrace-server>
  REGEX "AGONES_SDK_HTTP_PORT='9x' is not a port.*exit=2" LABELS quick ops TIMEOUT 20)
jetrace_cli_test(NAME cli_server_rejects_unbindable_metrics
  COMMAND sh -c "\"$0\" --port 0 --metrics 192.0.2.1:9100 2>&1; echo exit=$?" $<TARGET_FILE:jetrace-server>
  REGEX "--metrics: cannot listen on 192.0.2.1:9100.*exit=1" LABELS quick ops TIMEOUT 20)
