// Decodes glovesculpt's LCM channels with the Java classes lcm-gen makes from lcmtypes/lcm
// (build/lcmtypes/sculpt_lcm_types.jar, the classes lcm-spy loads), live or from a durable log:
//
//   java -cp lcm.jar:sculpt_lcm_types.jar:. DecodeSculptLcm live URL SECONDS
//   java -cp lcm.jar:sculpt_lcm_types.jar:. DecodeSculptLcm log FILE
//
// Prints one "CHANNEL count" line per channel and "undecodable N"; exits 1 when a message of a
// known channel does not decode (a wrong fingerprint or a cut message).
import java.io.EOFException;
import java.io.IOException;
import java.util.Map;
import java.util.TreeMap;
import lcm.lcm.LCM;
import lcm.lcm.LCMDataInputStream;
import lcm.lcm.LCMSubscriber;
import lcm.logging.Log;

public class DecodeSculptLcm {
  private static final Map<String, Integer> counts = new TreeMap<>();
  private static int undecodable = 0;
  private static long lastMessageMs = 0;

  private static synchronized void decode(String channel, byte[] data) {
    try {
      switch (channel) {
        case "SCULPT_SESSION": new sculpt_lcm.session_header_t(data); break;
        case "SCULPT_GLOVE": new sculpt_lcm.glove_sample_t(data); break;
        case "SCULPT_FINGERTIP": new sculpt_lcm.fingertip_state_t(data); break;
        case "SCULPT_COLLISION": new sculpt_lcm.collision_event_t(data); break;
        case "SCULPT_TICK": new sculpt_lcm.tick_stats_t(data); break;
        case "SCULPT_HAPTIC": new sculpt_lcm.haptic_command_t(data); break;
        case "SCULPT_CHECK": new sculpt_lcm.log_check_t(data); break;
        default: return;  // another program's channel
      }
      counts.merge(channel, 1, Integer::sum);
    } catch (IOException e) {
      ++undecodable;
      System.err.println(channel + ": does not decode: " + e.getMessage());
    }
    lastMessageMs = System.currentTimeMillis();
  }

  public static void main(String[] args) throws Exception {
    if (args.length == 3 && args[0].equals("live")) {
      LCM lcm = new LCM(args[1]);
      lcm.subscribeAll(new LCMSubscriber() {
        public void messageReceived(LCM from, String channel, LCMDataInputStream in) {
          try {
            byte[] data = new byte[in.available()];
            in.readFully(data);
            decode(channel, data);
          } catch (IOException e) {
            System.err.println(channel + ": cannot read: " + e.getMessage());
          }
        }
      });
      System.out.println("listening");  // the test starts the station after this line
      System.out.flush();
      long end = System.currentTimeMillis() + (long) (Double.parseDouble(args[2]) * 1000);
      // Until the time is up, or a second after the last message once there was one.
      while (System.currentTimeMillis() < end) {
        Thread.sleep(50);
        synchronized (DecodeSculptLcm.class) {
          if (lastMessageMs > 0 && System.currentTimeMillis() - lastMessageMs > 1000) break;
        }
      }
      lcm.close();
    } else if (args.length == 2 && args[0].equals("log")) {
      Log log = new Log(args[1], "r");
      try {
        while (true) {
          Log.Event e = log.readNext();
          decode(e.channel, e.data);
        }
      } catch (EOFException end) {
        // the end of the log
      }
      log.close();
    } else {
      System.err.println("usage: DecodeSculptLcm live URL SECONDS | log FILE");
      System.exit(2);
    }
    synchronized (DecodeSculptLcm.class) {
      for (Map.Entry<String, Integer> c : counts.entrySet()) System.out.println(c.getKey() + " " + c.getValue());
      System.out.println("undecodable " + undecodable);
      System.exit(undecodable == 0 ? 0 : 1);
    }
  }
}
