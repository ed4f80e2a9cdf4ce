//! The help texts of the programs that read their command line by hand
//! (LinuxCNC's option letters keep their meaning there). Each is what
//! `--help` prints and what the program's man page is made from
//! (`tests/man_pages.rs`), in one shape: `usage:` lines, a description,
//! then sections (`options:`, `examples:`, ...) of indented lines.

/// `halrun --help`.
pub const HALRUN: &str = "\
usage: halrun [-I] [halcmd options] [FILE.hal | FILE.tcl | MACHINE.ini]
       halrun -T [-i INI] [FILE.hal | FILE.tcl | MACHINE.ini]
       halrun -U
       halrun -h

Starts a HAL instance (its host, with the realtime threads), runs the file
on it, then stops the instance: .hal files with halcmd, .tcl files with
haltcl, and of a machine's .ini file only the [HAL]TWOPASS processing of
its HALFILEs, as LinuxCNC's halrun (an .ini file without TWOPASS is
refused; linuxcnc runs a whole machine). With -I an interactive halcmd follows the file (with line editing,
history and completion on a terminal); with -T an interactive haltcl.

options:
  -I               an interactive halcmd after the file (or alone, without a file)
  -T               an interactive haltcl after the file
  -U               stop the realtime environment of the instance
  -f FILE          the file to run (may also be given as the last argument)
  -i INI           substitute [SECTION]KEY from INI (.hal and .tcl files)
  -e -k -q -Q -s -v -V -R
                   halcmd's options, for .hal files (see halcmd --help)
  --instance NAME  the HAL instance (default $HAL_INSTANCE, else 'default')
  -h, --help       print this help and exit
  --version        print the version and exit

examples:
  halrun -f my.hal              run my.hal, then tear the instance down
  halrun -I my.hal              run my.hal, then an interactive halcmd
  halrun machine.ini            a TWOPASS machine's HALFILEs, as in pass 0 and 1
  halrun -U                     stop an instance left running";

/// `haltcl --help`.
pub const HALTCL: &str = "\
usage: haltcl [-i INI] [--instance NAME] [FILE.tcl [ARGS...]]

Runs a Tcl HAL file on a running HAL instance, or, without a file, an
interactive Tcl session: Tcl with the hal command and every halcmd command
(loadrt, net, setp, ...), INI values as Tcl arrays ($::KINS(JOINTS)).
It runs Debian's tclsh8.6 (package tcl8.6); HALTCL_TCLSH names another.

options:
  -i, -ini INI     read INI and give its sections as Tcl arrays
  --instance NAME  the HAL instance (default $HAL_INSTANCE, else 'default')
  -h, --help       print this help and exit
  --version        print the version and exit

examples:
  haltcl -i machine.ini machine.tcl
  haltcl                         an interactive session (realtime start first)";

/// `halmeter --help`.
pub const HALMETER: &str = "\
usage: halmeter [-i NAME] [-n COUNT] [-p PERIOD_MS] [pin|sig|param] NAME

Shows the value of one pin, signal or parameter of a running HAL instance,
updated in place on a terminal (one line per reading otherwise), until
Ctrl-C or COUNT readings. Without pin, sig or param the name is looked up
as a pin, then a signal, then a parameter.

options:
  -n COUNT             stop after COUNT readings
  -p PERIOD_MS         milliseconds between readings (default 100)
  -i, --instance NAME  the HAL instance (default $HAL_INSTANCE, else 'default')
  -h, --help           print this help and exit
  --version            print the version and exit

examples:
  halmeter pin servo.time
  halmeter -n 1 sig x-pos-cmd   one reading, for scripts";

/// `halsampler --help`.
pub const HALSAMPLER: &str = "\
usage: halsampler [-i NAME] [-c CHAN] [-n COUNT] [-t] [FILE]

Prints the samples that channel CHAN of the sampler component collects,
one line per sample, to FILE or standard output, until COUNT samples or
Ctrl-C. A gap in the sample numbers (the FIFO overflowed) prints a line
'overrun'. The exit status is 1 when the instance stops or Ctrl-C comes
before COUNT samples.

options:
  -c CHAN              the sampler channel (default 0)
  -n COUNT             stop after COUNT samples
  -t                   begin each line with the sample number
  -i, --instance NAME  the HAL instance (default $HAL_INSTANCE, else 'default')
  -h, --help           print this help and exit
  --version            print the version and exit

examples:
  halsampler -n 1000 run.samples   (after: loadrt sampler depth=1024 cfg=ff)";

/// `halstreamer --help`.
pub const HALSTREAMER: &str = "\
usage: halstreamer [-i NAME] [-c CHAN] [FILE]

Feeds lines of values from FILE or standard input into channel CHAN of the
streamer component: one line per sample, one value per pin of the
channel, separated by spaces (bit 0 or 1, float, s32, u32, ...). Lines
starting with # are skipped; a bad line (an empty one too) is reported
with its number and skipped. It waits while the FIFO is full.

options:
  -c CHAN              the streamer channel (default 0)
  -i, --instance NAME  the HAL instance (default $HAL_INSTANCE, else 'default')
  -h, --help           print this help and exit
  --version            print the version and exit

examples:
  halstreamer moves.txt   (after: loadrt streamer depth=1024 cfg=ff)";

/// `realtime --help`.
pub const REALTIME: &str = "\
usage: realtime [-i NAME] start|stop|restart|status

Starts or stops the HAL host of an instance, for tools to use from any
shell (halcmd, halmeter, motion-cmd, ...), as LinuxCNC's realtime script.
start returns once the host serves; its messages go to hal-NAME.log in the
runtime directory. stop returns once the host has exited and released
everything (or says it did not within 20 s). status exits 0 when the
instance runs, 1 when not.

options:
  -i, --instance NAME  the HAL instance (default $HAL_INSTANCE, else 'default')
  -h, --help           print this help and exit
  --version            print the version and exit

examples:
  realtime start && halcmd loadrt threads name1=servo period1=1000000
  HAL_INSTANCE=bench realtime stop";

/// `hal-host --help`.
pub const HAL_HOST: &str = "\
usage: hal-host [-i NAME]

Runs the HAL host of an instance until 'realtime stop', 'halrun -U' or a
signal: it creates the instance's shared memory, serves its control socket,
loads modules for loadrt and runs the realtime threads. halrun and
'realtime start' start it; it is not usually run by hand.

options:
  -i, --instance NAME  the HAL instance (default $HAL_INSTANCE, else 'default')
  -h, --help           print this help and exit
  --version            print the version and exit";

/// `task-cmd --help`: the options and every request task takes.
pub fn task_cmd() -> String {
    format!(
        "usage: task-cmd [-i NAME] [-t SECONDS] REQUEST [ARGS...]\n\n\
         Sends one request to the machine started by linuxcnc on the HAL instance\n\
         and prints the answer. Requests that wait for the HAL side (estop-reset,\n\
         tool changes) wait up to SECONDS (default 30). Exit status: 0 done,\n\
         1 refused, 2 usage or connection error.\n\n\
         options:\n\
         \x20 -i, --instance NAME   the HAL instance (default $HAL_INSTANCE, else 'default')\n\
         \x20 -t, --timeout SECONDS how long to wait for the answer (default 30)\n\
         \x20 -h, --help            print this help and exit\n\
         \x20 --version             print the version and exit\n\n\
         requests:\n{}\n\n\
         examples:\n\
         \x20 task-cmd estop-reset && task-cmd machine-on\n\
         \x20 task-cmd tool-change 3",
        hal_launcher::REQUESTS
    )
}

/// `inivar --help`.
pub const INIVAR: &str = "\
usage: inivar -var VARIABLE [-tildeexpand] [-sec SECTION] [-ini FILE] [-num N]

Prints the value of VARIABLE in an INI file, as the file has it, for shell
scripts (LinuxCNC's inivar). Without -sec the first VARIABLE of any
section is taken. Exit status 1 when it is not there (the message on
standard error names what was asked) or the command line is bad, 255 when
the file cannot be read.

options:
  -var VARIABLE        the key to print
  -sec SECTION         the section (without brackets) it is in
  -ini FILE            the INI file (default emc.ini)
  -num N               the Nth occurrence, from 1 (default 1)
  -tildeexpand         a leading ~ in the value becomes $HOME
  -h, --help           print this help and exit
  --version            print the version and exit

examples:
  inivar -var SERVO_PERIOD -sec EMCMOT -ini machine.ini
  inivar -var HALFILE -sec HAL -num 2 -ini machine.ini";
