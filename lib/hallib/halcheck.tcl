# halcheck.tcl: reports common mistakes of a HAL configuration, as the
# last [HAL]HALFILE: functions not added to any thread, signals without a
# writer, signals without a reader. It only reports (there is no popup on
# a headless machine; the `nopopup` argument is accepted).

proc halcheck_report {title items} {
  if {[llength $items] == 0} return
  puts "halcheck: $title:"
  foreach i $items {puts "    $i"}
}

set halcheck_added {}
foreach line [split [hal show thread] \n] {
  set f [regexp -all -inline {\S+} $line]
  if {[llength $f] == 2 && [string is integer [lindex $f 0]]} {
    lappend halcheck_added [lindex $f 1]
  }
}
set halcheck_unadded {}
foreach f [hal list funct] {
  if {[lsearch -exact $halcheck_added $f] < 0} {lappend halcheck_unadded $f}
}
halcheck_report "functions not added to a thread" $halcheck_unadded

set halcheck_nowriter {}
set halcheck_noreader {}
foreach s [hal list sig] {
  set writer 0
  set reader 0
  foreach line [lrange [split [hal show signal $s] \n] 2 end] {
    switch -- [lindex [regexp -all -inline {\S+} $line] 0] {
      "<==" {incr writer}
      "<=>" {incr writer; incr reader}
      "==>" {incr reader}
    }
  }
  if {!$writer} {lappend halcheck_nowriter $s}
  if {!$reader} {lappend halcheck_noreader $s}
}
halcheck_report "signals without a writer" $halcheck_nowriter
halcheck_report "signals without a reader" $halcheck_noreader
