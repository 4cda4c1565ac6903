# The COST of each test (ctest's test property): the seconds it took in CI's sanitizer build (the
# plain build's own tests: there). A fresh ctest starts the costliest tests first, so that the
# run does not end on one long test while the other core waits. Pairs of name and seconds,
# written by scripts/update_test_costs.py from the record of a run; refresh them after adding or
# changing tests that take more than a few seconds.
set(DXLEMU_TEST_COSTS
  app.check_accepts_a_robot_profile 0.1
  app.check_accepts_the_documented_example_config 0.1
  app.cpack_makes_a_deb 6.1
  app.install_finds_models_relative_to_the_binary 4.6
  app.models_filter_matching_nothing_says_so_on_stderr_and_exits_0 0.1
  app.models_filters_by_family_protocol_and_name 2.8
  app.models_lists_firmware_variants 1.0
  app.models_lists_the_library 1.2
  app.models_name_filter_matches_the_title_ignoring_case 0.1
  app.models_refuses_a_bad_file_naming_file_pointer_and_reason 0.1
  app.models_refuses_an_unknown_family_naming_the_known_ones 0.1
  app.prints_version 0.1
  app.robots_lists_the_pairs_with_the_command_that_serves_both 0.2
  app.robots_lists_the_profiles 0.1
  app.robots_refuses_a_bad_profile_naming_file_pointer_and_reason 0.1
  app.run_refuses_an_unknown_firmware_naming_the_known_ones 0.1
  app.run_refuses_an_unknown_robot_naming_the_known_ones 0.1
  app.run_refuses_robot_with_config 0.1
  docs.architecture_names_every_source_file 0.2
  docs.readme_documents_every_run_option 0.2
  docs.readme_lists_what_setup_installs 0.2
  docs.relative_links_resolve 0.2
  e2e.adapter 2.3
  e2e.clone 8.2
  e2e.control 2.1
  e2e.control_table 1.8
  e2e.ctl 1.3
  e2e.daemon 4.1
  e2e.exec 2.1
  e2e.feetech_session 0.8
  e2e.firmware 0.4
  e2e.hands 32.5
  e2e.hands_physics 6.0
  e2e.late_replies 2.4
  e2e.lerobot_flows 2.5
  e2e.pcap_dissector 3.0
  e2e.physics 0.4
  e2e.robot_pairs 0.5
  e2e.robot_pairs_physics 0.3
  e2e.robot_startup 1.9
  e2e.sdk_client 12.9
  e2e.settings 1.8
  examples.corrupted_replies_retry 0.6
  examples.overheat_reboot 2.3
  examples.unplug_replug 2.4
  fuzz.bus.smoke 4.6
  fuzz.bus_feetech.smoke 5.4
  fuzz.control.smoke 4.5
  fuzz.loaders.smoke 3.0
  fuzz.web.smoke 5.3
  fuzz.wire_feetech.smoke 2.2
  fuzz.wire_v1.smoke 6.1
  fuzz.wire_v2.smoke 5.9
  layering.core_has_no_asio_and_no_clock 0.1
  models.converter_output_is_current 3.8
  models.converter_unit 1.8
  models.feetech_converter_output_is_current 0.3
  models.feetech_converter_unit 0.2
  models.sdk_control_tables_agree 0.9
  models.sdk_control_tables_unit 0.2
  python.installed_tree_serves_the_plugin_and_its_binary 2.0
  python.package 5.8
  python.pip_install_offline_then_plain_pytest 7.2
  reliability.acknowledged_eeprom_write_survives_kill 3.1
  reliability.control_abuse 4.4
  reliability.garbage_soak 10.4
  reliability.late_replies 2.1
  reliability.pty_cycles 1.8
  reliability.state_kill 4.2
  reliability.unread_replies_do_not_pile_up 3.0
  tests.unit_cases_are_all_run_and_safely_named 0.5
  trajectories.shipped_are_generated 0.1
  unit.app.app_fuzz_findings 0.1
  unit.app.bus_config 0.2
  unit.app.bus_options 0.1
  unit.app.bus_state 0.2
  unit.app.command_line 0.2
  unit.app.ctl_request 0.1
  unit.app.exec_setup 0.1
  unit.app.hand_start 0.2
  unit.app.json_line 0.1
  unit.app.make_servo 0.1
  unit.app.model_library 1.1
  unit.app.pcap_writer 0.1
  unit.app.physics_config 0.1
  unit.app.port_link_chain 0.1
  unit.app.robot_library 0.5
  unit.app.state_keeper 0.1
  unit.app.trace_fan_out 0.1
  unit.app.trace_record 0.1
  unit.app.trajectory_file 1.9
  unit.app.web_address 0.1
  unit.bus.bus 0.2
  unit.bus.bus_fuzz_findings 0.2
  unit.bus.bus_rules 0.2
  unit.bus.catalogue_families 0.5
  unit.bus.coverage 0.3
  unit.bus.feetech_bus 0.2
  unit.bus.feetech_field_behaviour 0.2
  unit.bus.feetech_protection 0.3
  unit.bus.feetech_refusals 0.3
  unit.bus.firmware_variants 0.2
  unit.bus.late_reply_guard 0.1
  unit.bus.motion_bus 0.4
  unit.bus.read_request 0.1
  unit.bus.usb_adapter_link 0.1
  unit.control.api 0.3
  unit.control.control_fuzz_findings 0.1
  unit.control.eeprom_writes_stats 0.2
  unit.control.hand_commands 6.3
  unit.control.physics_scene 0.1
  unit.control.read_only 0.3
  unit.control.sample_commands 0.3
  unit.control.scenario_list 0.1
  unit.control.table_command 0.6
  unit.control.unit_text 2.8
  unit.faults.fault_bus 0.2
  unit.faults.injector 0.2
  unit.faults.port_faults 0.1
  unit.faults.rule_parser 0.1
  unit.io.atomic_file 0.1
  unit.io.child_process 0.1
  unit.io.control_server 0.2
  unit.io.pty_link 0.1
  unit.io.pty_list 0.1
  unit.io.realtime_driver 0.1
  unit.io.serial_device 0.1
  unit.io.socket_file 0.1
  unit.io.wake_lead 0.1
  unit.io.web_server 0.7
  unit.model.access_matrix 0.2
  unit.model.control_table 0.1
  unit.model.device_write 0.2
  unit.model.dynamixel_y 1.3
  unit.model.eeprom_writes 0.2
  unit.model.family_traits 0.1
  unit.model.hand_motion 0.2
  unit.model.model_fuzz_findings 0.1
  unit.model.model_loader 0.3
  unit.model.motion 2.1
  unit.model.profile 2.9
  unit.model.reading_settings 2.3
  unit.model.rest_values 2.5
  unit.model.servo 0.3
  unit.model.shipped_models 14.2
  unit.model.trajectory 0.1
  unit.model.value_encoding 0.3
  unit.physics.arm 0.3
  unit.physics.mujoco_scene 0.1
  unit.physics.pendulum 0.2
  unit.physics.physics_commands 0.1
  unit.physics.world_clock 0.1
  unit.scan.bus_scan 0.2
  unit.sim.rng 0.1
  unit.sim.scheduler 0.1
  unit.wire.checks 0.1
  unit.wire.decoder 0.1
  unit.wire.fast_reply 0.1
  unit.wire.feetech_decoder 0.1
  unit.wire.feetech_framer 0.1
  unit.wire.feetech_golden 0.1
  unit.wire.garbage 0.1
  unit.wire.golden 0.1
  unit.wire.raw_bytes 0.3
  unit.wire.split 0.1
  unit.wire.stuffing 0.1
  web.browser 7.3
  web.physics 3.7
  web.security 4.3
  wire.protocol_table_copies_agree 0.2
)

# dxlemu_apply_test_costs(): gives every test of the current directory that the table names its
# COST (test properties can only be set where the test was added).
function(dxlemu_apply_test_costs)
  set(pairs ${DXLEMU_TEST_COSTS})
  list(LENGTH pairs length)
  if(length EQUAL 0)
    return()
  endif()
  math(EXPR last "${length} - 1")
  foreach(i RANGE 0 ${last} 2)
    math(EXPR j "${i} + 1")
    list(GET pairs ${i} name)
    list(GET pairs ${j} cost)
    if(TEST ${name})
      set_tests_properties(${name} PROPERTIES COST ${cost})
    endif()
  endforeach()
endfunction()
