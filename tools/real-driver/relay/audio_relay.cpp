// ALAudioDevice for the real naoqi_driver, relayed from the fake NAOqi's Python service.
//
// naoqi_driver registers ROS-Driver-Audio, calls ALAudioDevice.setClientPreferences(
// "ROS-Driver-Audio", 48000, 0, 0) and subscribe("ROS-Driver-Audio") (src/event/audio.cpp:106-114);
// NAOqi then calls the module's processRemote(nbOfChannels, samplesByChannel, timestamp, buffer),
// whose buffer the driver reads with asRaw() (audio.cpp:175-186). A Python caller cannot send a
// Raw argument (qi 3.1.5 sends a bytes argument as its str() text), so this relay registers
// ALAudioDevice, forwards the preferences and subscriptions to the Python FakeAudioFrames, takes
// each buffer from FakeAudioFrames.next_buffer (typed "(iiiir)": the Raw is a return value,
// which Python can send; the Python side keeps the real-time pace) and calls processRemote.
//
//   audio_relay tcp://127.0.0.1:9559
#include <iostream>
#include <map>
#include <string>
#include <vector>
#include <boost/function.hpp>
#include <boost/make_shared.hpp>
#include <boost/shared_ptr.hpp>
#include <boost/thread.hpp>
#include <qi/anyobject.hpp>
#include <qi/buffer.hpp>
#include <qi/session.hpp>
#include <qi/type/dynamicobjectbuilder.hpp>

namespace {

// one subscribed module: a thread taking buffers and calling the module's processRemote
void deliver(qi::SessionPtr session, qi::AnyObject frames, std::string module,
             boost::shared_ptr<bool> running)
{
  qi::AnyObject target;
  int failures = 0, delivered = 0;
  while (*running) {
    qi::AnyValue typed;
    try {
      typed = frames.call<qi::AnyValue>("next_buffer", module);
    } catch (const std::exception& e) {
      if (*running) std::cerr << "audio relay: next_buffer: " << e.what() << std::endl;
      boost::this_thread::sleep_for(boost::chrono::milliseconds(100));
      continue;
    }
    qi::AnyReferenceVector f = typed.asTupleValuePtr();
    int nbOfChannels = f[0].toInt(), samplesByChannel = f[1].toInt();
    std::vector<int> timestamp;
    timestamp.push_back(f[2].toInt());
    timestamp.push_back(f[3].toInt());
    std::pair<char*, size_t> raw = f[4].asRaw();
    qi::Buffer buffer;
    buffer.write(raw.first, raw.second);
    try {
      if (!target) target = session->service(module).value();
      target.call<void>("processRemote", nbOfChannels, samplesByChannel,
                        qi::AnyValue::from(timestamp), qi::AnyValue::from(buffer));
      ++delivered;
    } catch (const std::exception& e) {
      target = qi::AnyObject();
      if (failures++ % 20 == 0)
        std::cerr << "audio relay: processRemote on " << module << " (after " << delivered
                  << " buffers delivered): " << e.what() << std::endl;
    }
  }
  std::cout << "audio relay: " << module << " stopped after " << delivered << " buffers" << std::endl;
}

}  // namespace

int main(int argc, char** argv)
{
  if (argc < 2) {
    std::cerr << "usage: audio_relay <url of the fake NAOqi>" << std::endl;
    return 2;
  }
  qi::SessionPtr session = qi::makeSession();
  session->connect(argv[1]).value();
  qi::AnyObject frames = session->service("FakeAudioFrames").value();
  boost::shared_ptr<boost::mutex> lock = boost::make_shared<boost::mutex>();
  boost::shared_ptr<std::map<std::string, boost::shared_ptr<bool> > > running =
    boost::make_shared<std::map<std::string, boost::shared_ptr<bool> > >();

  boost::function<void(const std::string&, int, int, int)> preferences =
    [frames](const std::string& module, int rate, int channels, int deinterleaved) {
      frames.call<void>("setClientPreferences", module, rate, channels, deinterleaved != 0);
    };
  boost::function<void(const std::string&)> stop = [frames, lock, running](const std::string& module) {
    boost::mutex::scoped_lock l(*lock);
    if (running->count(module)) {
      *(*running)[module] = false;
      running->erase(module);
    }
    frames.call<void>("unsubscribe", module);
  };
  boost::function<void(const std::string&)> subscribe =
    [session, frames, lock, running](const std::string& module) {
      frames.call<void>("subscribe", module);
      boost::mutex::scoped_lock l(*lock);
      if (running->count(module)) *(*running)[module] = false;
      boost::shared_ptr<bool> flag = boost::make_shared<bool>(true);
      (*running)[module] = flag;
      boost::thread(deliver, session, frames, module, flag).detach();
      std::cout << "audio relay: " << module << " subscribed" << std::endl;
    };
  qi::DynamicObjectBuilder builder;
  builder.advertiseMethod("setClientPreferences", preferences);
  builder.advertiseMethod("subscribe", subscribe);
  builder.advertiseMethod("unsubscribe", stop);
  session->registerService("ALAudioDevice", builder.object()).value();
  std::cout << "audio relay ready" << std::endl;
  qi::Promise<void> forever;
  forever.future().wait();
  return 0;
}
